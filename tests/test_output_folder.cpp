// The output folder is protected (docs/output-format.md, docs/reliability.md), tested with real salsa
// processes: one writer per folder (a second run at once is refused naming the holder; two queues
// started together into one empty folder: one wins; Slurm array tasks share it, a task without its
// count is refused; --isolate children run under their parent's lock), output folders do not nest,
// summarize leaves folders without salsa results alone, and --resume checks the data, not a marker.
#include <sys/mount.h>
#include <unistd.h>

#include <QProcess>
#include <QThread>

#include <csignal>
#include <cerrno>

#include "salsa/core/files/csv_writer.hpp"
#include "common.hpp"

using namespace salsa_test;

namespace {

void write(const QString& path, const QByteArray& text) { QVERIFY(write_file(path, text)); }

/// A test that runs for minutes (thousands of drones), so that it is still running when the next
/// process starts; it is stopped with SIGINT.
const QByteArray long_test = R"({"name": "long", "behavior": "flocking", "drones": 3000, "time": 600})";

QByteArray small_queue(const QString& prefix, int n) {
  QByteArray q = "[";
  for (int i = 0; i < n; ++i)
    q += QStringLiteral(R"(%1{"name": "%2%3", "behavior": "random_walk", "drones": 5, "time": 1, "seed": %3})")
             .arg(i ? "," : "")
             .arg(prefix)
             .arg(i)
             .toUtf8();
  return q + "]";
}

/// salsa started in the background, with a clean environment plus `vars`.
std::unique_ptr<QProcess> start_salsa(const QStringList& args, const QString& dir, const QMap<QString, QString>& vars = {}) {
  static QTemporaryDir home;
  auto p = std::make_unique<QProcess>();
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.remove("SALSA_PLUGIN_PATH");
  env.remove("SLURM_ARRAY_TASK_ID");
  env.remove("SLURM_ARRAY_TASK_COUNT");
  env.insert("HOME", home.path());
  for (auto it = vars.begin(); it != vars.end(); ++it) env.insert(it.key(), it.value());
  p->setProcessEnvironment(env);
  p->setWorkingDirectory(dir);
  p->start(salsa_executable(), args);
  p->waitForStarted(30000);
  return p;
}

CliResult finish(QProcess& p) {
  p.waitForFinished(300000);
  CliResult r;
  r.crashed = p.exitStatus() != QProcess::NormalExit;
  r.exit_code = p.exitCode();
  r.out = QString::fromUtf8(p.readAllStandardOutput());
  r.err = QString::fromUtf8(p.readAllStandardError());
  return r;
}

CliResult run_env(const QStringList& args, const QString& dir, const QMap<QString, QString>& vars = {}) {
  auto p = start_salsa(args, dir, vars);
  return finish(*p);
}

bool wait_for(const QString& file) {
  for (int i = 0; i < 6000; ++i) {
    if (QFileInfo::exists(file)) return true;
    QThread::msleep(10);
  }
  return false;
}

bool one_line(const CliResult& r, const QString& expect) { return r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.err.contains(expect); }

}  // namespace

class TestOutputFolder : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  void second_run_into_the_same_folder_is_refused() {
    QTemporaryDir dir;
    write(dir.filePath("long.json"), long_test);
    auto first = start_salsa({"run", "long.json", "--out", "out", "--no-plots", "-q", "--threads", "1"}, dir.path());
    QVERIFY(wait_for(dir.filePath("out/.long.partial/summary.csv")));
    const QString pid = QString::number(first->processId());
    // The same queue, and the same queue with --force or --resume: all refused while it runs.
    for (const QStringList& more : {QStringList{}, QStringList{"--force"}, QStringList{"--resume"}}) {
      const CliResult r = run_env(QStringList{"run", "long.json", "--out", "out", "--no-plots"} + more, dir.path());
      QVERIFY2(one_line(r, "--out: out is being written by another salsa run (pid " + pid + " on host "), describe(r));
      QVERIFY2(r.err.contains("salsa run long.json --out out"), describe(r));  // the holder's command
      QVERIFY(QFileInfo::exists(dir.filePath("out/.long.partial/summary.csv")));  // the first run's rows are untouched
    }
    ::kill(static_cast<pid_t>(first->processId()), SIGINT);
    const CliResult stopped = finish(*first);
    QVERIFY2(stopped.exit_code == 130, describe(stopped));
    QVERIFY(!QFileInfo::exists(dir.filePath("out/.salsa.lock")));  // removed by its holder
  }

  void two_queues_into_one_empty_folder_one_wins() {
    QTemporaryDir dir;
    write(dir.filePath("a.json"), small_queue("a", 4));
    write(dir.filePath("b.json"), small_queue("b", 4));
    for (int round = 0; round < 3; ++round) {
      const QString out = QString("out%1").arg(round);
      auto a = start_salsa({"run", "a.json", "--out", out, "--no-plots", "-q", "--jobs", "1"}, dir.path());
      auto b = start_salsa({"run", "b.json", "--out", out, "--no-plots", "-q", "--jobs", "1"}, dir.path());
      const CliResult ra = finish(*a), rb = finish(*b);
      QVERIFY2((ra.exit_code == 0) != (rb.exit_code == 0), qPrintable(describe(ra) + describe(rb)));
      const CliResult& loser = ra.exit_code == 0 ? rb : ra;
      const QString winner = ra.exit_code == 0 ? "a" : "b";
      QVERIFY2(loser.exit_code == 2 && non_empty_lines(loser.err).size() == 1, describe(loser));
      QVERIFY2(loser.err.contains("is being written by another salsa run") || loser.err.contains("holds the results of another queue"),
               describe(loser));
      // The record and the summary are the winner's alone.
      const QByteArray record = read_file(dir.filePath(out + "/queue.json"));
      QVERIFY2(record.contains("\"" + winner.toUtf8() + "0\"") && !record.contains(winner == "a" ? "\"b0\"" : "\"a0\""), record.constData());
      const QStringList rows = non_empty_lines(QString::fromUtf8(read_file(dir.filePath(out + "/summary.csv"))));
      QCOMPARE(rows.size(), 5);
      for (int i = 1; i < rows.size(); ++i) QVERIFY2(rows[i].startsWith(winner) && rows[i].contains(",ok,"), qPrintable(rows[i]));
    }
  }

  void array_tasks_share_the_folder() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue("t", 6));
    QVERIFY(run_env({"run", "q.json", "--out", "whole", "-q", "--no-plots"}, dir.path()).exit_code == 0);
    auto zero = start_salsa({"run", "q.json", "--out", "out", "-q", "--no-plots"}, dir.path(),
                            {{"SLURM_ARRAY_TASK_ID", "0"}, {"SLURM_ARRAY_TASK_COUNT", "2"}});
    auto one = start_salsa({"run", "q.json", "--out", "out", "-q", "--no-plots"}, dir.path(),
                           {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_COUNT", "2"}});
    const CliResult r0 = finish(*zero), r1 = finish(*one);
    QVERIFY2(r0.exit_code == 0 && r1.exit_code == 0, qPrintable(describe(r0) + describe(r1)));
    QVERIFY(run_env({"summarize", "out", "-q", "--no-plots"}, dir.path()).exit_code == 0);
    QCOMPARE(results_snapshot(dir.filePath("out")), results_snapshot(dir.filePath("whole")));
  }

  void array_task_without_count_is_refused() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue("t", 2));
    const auto before = snapshot(dir.path());
    const CliResult r = run_env({"run", "q.json", "--out", "out"}, dir.path(), {{"SLURM_ARRAY_TASK_ID", "3"}});
    QVERIFY2(one_line(r, "SLURM_ARRAY_TASK_ID: 3 is set without SLURM_ARRAY_TASK_COUNT"), describe(r));
    QCOMPARE(snapshot(dir.path()), before);
  }

  void same_array_task_twice_and_another_split_are_refused() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), "[" + long_test + R"(, {"name": "b", "behavior": "flocking", "drones": 3000, "time": 600, "seed": 4}])");
    auto first = start_salsa({"run", "q.json", "--out", "out", "-q", "--no-plots", "--threads", "1"}, dir.path(),
                             {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_COUNT", "2"}});
    QVERIFY(wait_for(dir.filePath("out/.b.partial/summary.csv")));
    CliResult r = run_env({"run", "q.json", "--out", "out", "--no-plots"}, dir.path(),
                          {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_COUNT", "2"}});
    QVERIFY2(one_line(r, "--out: out: shard 1/2 is being run already (shard 1/2 pid " + QString::number(first->processId())), describe(r));
    r = run_env({"run", "q.json", "--out", "out", "--no-plots", "--shard", "0/3"}, dir.path());
    QVERIFY2(one_line(r, "shard 1/2 of another split is running"), describe(r));
    r = run_env({"run", "q.json", "--out", "out", "--no-plots"}, dir.path());  // the whole queue
    QVERIFY2(one_line(r, "--out: out is being written by another salsa run (shard 1/2 pid"), describe(r));
    ::kill(static_cast<pid_t>(first->processId()), SIGINT);
    QCOMPARE(finish(*first).exit_code, 130);
    QVERIFY(QDir(dir.filePath("out")).entryList({".salsa*lock"}, QDir::Files | QDir::Hidden).isEmpty());
  }

  void isolate_children_run_under_their_parents_lock() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue("t", 3));
    const CliResult r = run_env({"run", "q.json", "--out", "out", "--isolate", "--jobs", "2", "-q", "--no-plots"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    for (int i = 0; i < 3; ++i) QVERIFY(QFileInfo::exists(dir.filePath(QString("out/t%1/config.json").arg(i))));
    QVERIFY(!QFileInfo::exists(dir.filePath("out/.salsa.lock")));
  }

  void output_folders_do_not_nest() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue("t", 2));
    QVERIFY(run_env({"run", "q.json", "--out", "out", "-q", "--no-plots"}, dir.path()).exit_code == 0);
    const auto before = snapshot(dir.path());
    // Rerunning a test the way one might: its config.json into its own folder, or below it.
    CliResult r = run_env({"run", "out/t0/config.json", "--out", "out/t0"}, dir.path());
    QVERIFY2(one_line(r, "--out: out/t0 is a test folder salsa wrote (allowed: a folder outside the folders salsa writes"), describe(r));
    r = run_env({"run", "out/t0/config.json", "--out", "out/t0/again"}, dir.path());
    QVERIFY2(one_line(r, "--out: out/t0/again is inside"), describe(r));
    r = run_env({"run", "out/t0/config.json", "--out", "out/again"}, dir.path());
    QVERIFY2(one_line(r, "the output folder of a queue salsa wrote"), describe(r));
    QCOMPARE(snapshot(dir.path()), before);
    // Results nested by hand (or by an older salsa) inside a test folder: --force will not delete them.
    QVERIFY(QDir().mkpath(dir.filePath("out/t1/inner/x")));
    write(dir.filePath("out/t1/inner/x/.salsa-test"), "");
    const auto nested = snapshot(dir.path());
    r = run_env({"run", "q.json", "--out", "out", "--force"}, dir.path());
    QVERIFY2(one_line(r, "out/t1: holds salsa results of its own (out/t1/inner/x), which replacing it would delete"), describe(r));
    QCOMPARE(snapshot(dir.path()), nested);
  }

  void summarize_leaves_other_folders_alone() {
    QTemporaryDir dir;
    write(dir.filePath("mine/summary.csv"), "my,own\n1,2\n");
    write(dir.filePath("mine/comparison.csv"), "also,mine\n");
    for (const char* file : {"tune.json", "candidates.csv", "tune_plots.json"}) write(dir.filePath(QString("mine/") + file), "mine too\n");  // not a tune's
    const auto before = snapshot(dir.path());
    CliResult r = run_env({"summarize", "mine"}, dir.path());
    QVERIFY2(one_line(r, "mine: holds no salsa results"), describe(r));
    r = run_env({"plot", "mine"}, dir.path());
    QVERIFY2(one_line(r, "mine: neither a test folder"), describe(r));
    QCOMPARE(snapshot(dir.path()), before);
  }

  void resume_checks_what_a_finished_test_holds() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue("t", 3));
    QVERIFY(run_env({"run", "q.json", "--out", "whole", "-q", "--no-plots"}, dir.path()).exit_code == 0);
    QVERIFY(run_env({"run", "q.json", "--out", "out", "-q", "--no-plots"}, dir.path()).exit_code == 0);
    QVERIFY(QFile::remove(dir.filePath("out/t0/drones.csv")));
    QFile cut(dir.filePath("out/t1/summary.csv"));
    QVERIFY(cut.resize(cut.size() / 2));
    // summarize says so, naming the file
    CliResult r = run_env({"summarize", "out", "-q", "--no-plots"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QString summary = QString::fromUtf8(read_file(dir.filePath("out/summary.csv")));
    QVERIFY2(summary.contains("t0,incomplete,out/t0/drones.csv is missing (it was written)"), qPrintable(summary));
    QVERIFY2(summary.contains("t1,incomplete,out/t1/summary.csv is "), qPrintable(summary));
    // --resume reruns those two (salsa's folders) and skips the whole one; the data comes back identical.
    r = run_env({"run", "q.json", "--out", "out", "--resume", "--no-plots"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.out.contains("t2: already complete, skipped") && !r.out.contains("t0: already") &&
                 !r.out.contains("t1: already"),
             describe(r));
    QCOMPARE(results_snapshot(dir.filePath("out")), results_snapshot(dir.filePath("whole")));
    // A run without drones.csv is not complete when drones.csv is wanted.
    QVERIFY(run_env({"run", "q.json", "--out", "lean", "-q", "--no-plots", "--no-drones-csv"}, dir.path()).exit_code == 0);
    QVERIFY(!QFileInfo::exists(dir.filePath("lean/t0/drones.csv")));
    r = run_env({"run", "q.json", "--out", "lean", "--resume", "-q", "--no-plots", "--no-drones-csv"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    r = run_env({"run", "q.json", "--out", "lean", "--resume", "--no-plots"}, dir.path());
    QVERIFY2(r.exit_code == 0 && !r.out.contains("already complete"), describe(r));
    QCOMPARE(results_snapshot(dir.filePath("lean")), results_snapshot(dir.filePath("whole")));
    // A folder salsa did not write is never rerun into: refused, naming what is missing.
    QVERIFY(QFile::remove(dir.filePath("lean/t2/.salsa-test")));
    QVERIFY(QFile::remove(dir.filePath("lean/t2/targets.csv")));
    r = run_env({"run", "q.json", "--out", "lean", "--resume", "--no-plots"}, dir.path());
    QVERIFY2(one_line(r, "lean/t2/targets.csv is missing (it was written); --resume would rerun the test, but salsa did not write it"),
             describe(r));
  }

  void drones_csv_takes_state_columns_by_name() {
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "t", "behavior": "random_walk", "drones": 3, "time": 2, "log_interval": 0.5, "seed": 4,
      "map": {"name": "empty", "params": {"size": 200}}, "drone": {"battery_capacity": 50},
      "changes": [{"time": 1, "set": {"wind.velocity.x": 2}}]})");
    CliResult r = run_env({"run", "t.json", "--out", "out", "-q", "--no-plots", "--drone-columns", "battery_left,air_velocity,failure_due"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QStringList rows = QString::fromUtf8(read_file(dir.filePath("out/t/drones.csv"))).split('\n', Qt::SkipEmptyParts);
    QCOMPARE(rows[0], QString("time,id,x,y,vx,vy,group,status,energy_used_Wh,battery_left,air_velocity_x,air_velocity_y,failure_due"));
    double drawn = 0;
    for (const QString& row : rows.mid(1)) {
      const QStringList f = row.split(',');
      QCOMPARE(f.size(), 13);
      // battery_left (J) is the 50 Wh battery less the energy drawn (Wh, 4 decimals): the simulation's own column.
      QVERIFY2(std::abs(f[9].toDouble() - (50 - f[8].toDouble()) * 3600) < 0.5, qPrintable(row));
      // The wind's columns are empty until the wind first blows, then hold the air velocity.
      QCOMPARE(f[10].isEmpty(), f[0].toDouble() <= 1);  // the change comes before the step that starts at 1 s
      if (f[0].toDouble() > 1) QVERIFY2(std::abs(f[10].toDouble() - (f[4].toDouble() - 2)) < 1e-3, qPrintable(row));
      drawn = std::max(drawn, f[8].toDouble());
    }
    QVERIFY(drawn > 0);
    // A name that is no column, or one drones.csv has already, is refused in one line before anything runs.
    r = run_env({"run", "t.json", "--out", "bad", "--drone-columns", "battery"}, dir.path());
    QVERIFY2(one_line(r, "--drone-columns: 'battery' is not a drone state column (allowed: steering, commanded, status_since, camera_works, energy_used, battery_left,"), describe(r));
    r = run_env({"run", "t.json", "--out", "bad", "--drone-columns", "position"}, dir.path());
    QVERIFY2(one_line(r, "--drone-columns: 'position' is in drones.csv already"), describe(r));
    QVERIFY(!QFileInfo::exists(dir.filePath("bad")));
    // --resume keeps the test while its drones.csv has the columns asked for, and reruns it for others.
    r = run_env({"run", "t.json", "--out", "out", "--resume", "--no-plots", "--drone-columns", "air_velocity"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.out.contains("already complete"), describe(r));
    r = run_env({"run", "t.json", "--out", "out", "--resume", "--no-plots", "--drone-columns", "wind"}, dir.path());
    QVERIFY2(r.exit_code == 0 && !r.out.contains("already complete"), describe(r));
    QVERIFY(read_file(dir.filePath("out/t/drones.csv")).startsWith("time,id,x,y,vx,vy,group,status,energy_used_Wh,wind_x,wind_y\n"));
  }

  void write_errors_say_what_happened() {
    QCOMPARE(salsa::write_failure(EROFS), std::string("read-only file system"));
    QCOMPARE(salsa::write_failure(EACCES), std::string("permission denied"));
    QCOMPARE(salsa::write_failure(ENOSPC), std::string("disk full"));
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "t", "behavior": "flocking", "drones": 3, "time": 1})");
    const QString out = dir.filePath("out");
    QVERIFY(QDir().mkpath(out));
    QString expect;
    if (::geteuid() == 0) {  // root writes into any folder: a read-only file system instead
      if (::mount("tmpfs", out.toLocal8Bit().constData(), "tmpfs", MS_RDONLY, "size=1m") != 0) QSKIP("cannot mount a tmpfs here");
      expect = "read-only file system";
    } else {
      QVERIFY(QFile::setPermissions(out, QFileDevice::ReadOwner | QFileDevice::ExeOwner));
      expect = "permission denied";
    }
    const CliResult r = run_env({"run", "t.json", "--out", "out"}, dir.path());
    if (::geteuid() == 0) ::umount2(out.toLocal8Bit().constData(), MNT_DETACH);
    else QFile::setPermissions(out, QFileDevice::ReadOwner | QFileDevice::WriteOwner | QFileDevice::ExeOwner);
    QVERIFY2(one_line(r, "--out: out: cannot create the lock file out/.salsa.lock (" + expect) && !r.err.contains("disk full"), describe(r));
  }
};

QTEST_GUILESS_MAIN(TestOutputFolder)
#include "test_output_folder.moc"
