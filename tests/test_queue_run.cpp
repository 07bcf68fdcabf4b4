// Running queues with the real `salsa` CLI: tests side by side (--jobs) give the same files as one at a
// time; a failed test keeps its .partial folder with error.txt and the queue goes on; an interrupted or
// killed parallel run resumes to byte-identical results; OUT/queue.json refuses another queue's folder;
// OUT/summary.csv has a row per test; shards and MPI ranks each run their share exactly once.
#include <unistd.h>

#include <QElapsedTimer>
#include <QStandardPaths>
#include <QThread>

#include <csignal>

#include "common.hpp"

using namespace salsa_test;

namespace {

void write(const QString& path, const QByteArray& text) { QVERIFY(write_file(path, text)); }

/// A queue of `n` small tests, alternating behaviors and seeds.
QByteArray small_queue(int n, double time = 5, int drones = 10) {
  QByteArray q = "[";
  for (int i = 0; i < n; ++i)
    q += QStringLiteral(R"(%1{"name": "t%2", "behavior": "%3", "drones": %4, "time": %5, "targets": {"count": 5}, "seed": %2})")
             .arg(i ? "," : "")
             .arg(i)
             .arg(i % 2 ? "random_walk" : "flocking")
             .arg(drones)
             .arg(time)
             .toUtf8();
  return q + "]";
}

/// summary.csv as rows of fields (no quoted commas in what these tests write, error aside).
QList<QStringList> csv_rows(const QString& file) {
  QList<QStringList> rows;
  for (const QString& line : non_empty_lines(QString::fromUtf8(read_file(file)))) rows << line.split(',');
  return rows;
}

/// Runs salsa with extra environment variables (as run_salsa otherwise).
bool wait_for(const QString& file) {
  for (int i = 0; i < 6000; ++i) {
    if (QFileInfo::exists(file)) return true;
    QThread::msleep(10);
  }
  return false;
}

QString crash_plugins() { return q(test_plugins_dir() / "crash"); }

}  // namespace

class TestQueueRun : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  // A run killed while a test's plots are drawn publishes no half-drawn plot: they are drawn aside
  // (TEST/.plots.partial/) and put in place whole, and --resume draws the plots of a finished test that
  // has none. Here the kill is staged: the plots of a finished test gone, a cut-off PNG left aside.
  void resume_redraws_cut_off_plots() {
    QTemporaryDir dir;
    write_file(dir.filePath("t.json"), R"({"name": "t", "behavior": "random_walk", "drones": 3, "time": 2})");
    CliResult r = run_salsa({"run", "t.json", "--out", "out", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QString plots = dir.filePath("out/t/plots");
    const QStringList drawn = QDir(plots).entryList({"*.png"}, QDir::Files, QDir::Name);
    QVERIFY(drawn.contains("found.png"));
    QVERIFY(!QFileInfo::exists(dir.filePath("out/t/.plots.partial")));
    auto whole_png = [](const QString& file) {
      const QByteArray b = read_file(file);
      return b.startsWith("\x89PNG\r\n\x1a\n") && b.endsWith(QByteArray("IEND\xae\x42\x60\x82", 8));
    };
    for (const QString& f : drawn) QVERIFY2(whole_png(plots + "/" + f), qPrintable(f));
    // Killed mid-drawing: no plots/ yet, a truncated PNG in the folder aside.
    QVERIFY(QDir(plots).removeRecursively());
    QVERIFY(QDir().mkpath(dir.filePath("out/t/.plots.partial")));
    write_file(dir.filePath("out/t/.plots.partial/found.png"), "\x89PNG cut");
    r = run_salsa({"run", "t.json", "--out", "out", "-q", "--resume"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(QDir(plots).entryList({"*.png"}, QDir::Files, QDir::Name), drawn);
    for (const QString& f : drawn) QVERIFY2(whole_png(plots + "/" + f), qPrintable(f));
    QVERIFY(!QFileInfo::exists(dir.filePath("out/t/.plots.partial")));

    // A real SIGKILL while the plots are drawn (once the folder aside appears): what is published is
    // whole, and --resume completes it.
    write_file(dir.filePath("k.json"), R"({"name": "k", "behavior": "random_walk", "drones": 50, "time": 60})");
    QProcess run;
    run.setWorkingDirectory(dir.path());
    run.start(salsa_executable(), {"run", "k.json", "--out", "killed", "-q"});
    QVERIFY(run.waitForStarted(30000));
    QVERIFY(wait_for(dir.filePath("killed/k/.plots.partial")));
    ::kill(static_cast<pid_t>(run.processId()), SIGKILL);
    run.waitForFinished(60000);
    const QString killed = dir.filePath("killed/k/plots");
    for (const QString& f : QDir(killed).entryList({"*"}, QDir::Files)) QVERIFY2(whole_png(killed + "/" + f), qPrintable(f));
    r = run_salsa({"run", "k.json", "--out", "killed", "-q", "--resume"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(QDir(killed).entryList({"*.png"}, QDir::Files).contains("found.png"));
    for (const QString& f : QDir(killed).entryList({"*"}, QDir::Files)) QVERIFY2(whole_png(killed + "/" + f), qPrintable(f));
  }

  void jobs_give_the_same_files_data() {
    QTest::addColumn<QStringList>("options");
    QTest::newRow("--jobs 2") << QStringList{"--jobs", "2"};
    QTest::newRow("--jobs 3 --threads 2") << QStringList{"--jobs", "3", "--threads", "2"};
    QTest::newRow("default (all cores)") << QStringList{};
  }
  void jobs_give_the_same_files() {
    QFETCH(QStringList, options);
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue(8));
    CliResult r = run_salsa({"run", "q.json", "--out", "one", "--jobs", "1", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    r = run_salsa(QStringList{"run", "q.json", "--out", "many", "-q"} + options, dir.path());
    QVERIFY2(r.exit_code == 0 && r.out.isEmpty() && r.err.isEmpty(), describe(r));
    const auto one = results_snapshot(dir.filePath("one")), many = results_snapshot(dir.filePath("many"));
    QCOMPARE(one.size(), 8 * 8 + 3);  // per test .salsa-test, config.json, manifest.json, map.json, summary, drones, targets, outcome; summary.csv, comparison.csv, ranking.csv
    QCOMPARE(many, one);
    // timing.json: wall seconds and steps (5 s at 60 steps per second).
    for (int i = 0; i < 8; ++i) {
      const QByteArray timing = read_file(dir.filePath(QString("many/t%1/timing.json").arg(i)));
      QVERIFY2(timing.startsWith("{\"wall_seconds\": ") && timing.contains("\"steps\": 300}"), timing.constData());
    }
  }

  void progress_lines_and_quiet() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue(4, 2));
    CliResult r = run_salsa({"run", "q.json", "--out", "out", "--jobs", "2"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    const QStringList lines = non_empty_lines(r.out);
    QCOMPARE(lines.size(), 5);  // one per test (not a terminal: no bar), then "results in out"
    for (int i = 0; i < 4; ++i)
      QVERIFY2(lines.filter(QRegularExpression(QString("^\\[%1/4\\] t%2: 2.00 s simulated in .* targets found -> out/t%2$").arg(i + 1).arg(i))).size() == 1,
               describe(r));
    QCOMPARE(lines.last(), QString("results in out"));
  }

  void failed_test_keeps_its_partial_folder_and_the_queue_goes_on() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), R"([
      {"name": "before", "behavior": "flocking", "drones": 4, "time": 2, "seed": 1},
      {"name": "boom", "behavior": {"name": "test_crash", "params": {"mode": 3}}, "drones": 4, "time": 2},
      {"name": "after", "behavior": "flocking", "drones": 4, "time": 2, "seed": 2}])");
    const CliResult r = run_salsa({"run", "q.json", "--out", "out", "--jobs", "2", "--plugin-dir", crash_plugins(), "-q"}, dir.path());
    QVERIFY2(r.exit_code == 1 && !r.crashed && non_empty_lines(r.err).size() == 1 && r.err.contains("test 'boom'"), describe(r));
    const QStringList error = non_empty_lines(QString::fromUtf8(read_file(dir.filePath("out/.boom.partial/error.txt"))));
    QVERIFY2(error.size() == 1 && error[0].contains("test 'boom' (q.json: [1])") && error[0].contains("crash plugin threw as asked"),
             qPrintable(error.join('\n')));
    const auto rows = csv_rows(dir.filePath("out/summary.csv"));
    QCOMPARE(rows.size(), 4);
    QCOMPARE(rows[1].mid(0, 2), (QStringList{"before", "ok"}));
    QCOMPARE(rows[2].mid(0, 2), (QStringList{"boom", "failed"}));
    QVERIFY(rows[2][2].contains("crash plugin threw as asked"));
    QCOMPARE(rows[3].mid(0, 2), (QStringList{"after", "ok"}));
    // --resume reruns only the failed test (which fails again the same way).
    const CliResult again = run_salsa({"run", "q.json", "--out", "out", "--resume", "--plugin-dir", crash_plugins()}, dir.path());
    QVERIFY2(again.exit_code == 1 && again.out.count("already complete, skipped") == 2, describe(again));
  }

  void crash_line_names_the_crashing_test_among_several() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), R"([
      {"name": "long", "behavior": "flocking", "drones": 50, "time": 60},
      {"name": "boom", "behavior": {"name": "test_crash", "params": {"mode": 1}}, "drones": 4, "time": 2}])");
    const CliResult r = run_salsa({"run", "q.json", "--out", "out", "--jobs", "2", "--plugin-dir", crash_plugins()}, dir.path());
    QVERIFY2(r.crashed && non_empty_lines(r.err).size() == 1, describe(r));
    QVERIFY2(r.err.startsWith("salsa: test 'boom' (q.json: [1]) died of SIGSEGV (segmentation fault) at step 30 of 120"), describe(r));
  }

  void isolate_runs_side_by_side() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), R"([
      {"name": "a", "behavior": "flocking", "drones": 4, "time": 2, "seed": 1},
      {"name": "boom", "behavior": {"name": "test_crash", "params": {"mode": 1}}, "drones": 4, "time": 2},
      {"name": "b", "behavior": "flocking", "drones": 4, "time": 2, "seed": 2},
      {"name": "c", "behavior": "random_walk", "drones": 4, "time": 2, "seed": 3}])");
    const CliResult r =
        run_salsa({"run", "q.json", "--out", "out", "--isolate", "--jobs", "2", "--plugin-dir", crash_plugins(), "-q"}, dir.path());
    QVERIFY2(r.exit_code == 1 && !r.crashed && non_empty_lines(r.err).size() == 1 && r.err.contains("test 'boom'") &&
                 r.err.contains("SIGSEGV"),
             describe(r));
    for (const char* name : {"a", "b", "c"}) QVERIFY(QFileInfo::exists(dir.filePath(QString("out/") + name + "/config.json")));
    QVERIFY(read_file(dir.filePath("out/.boom.partial/error.txt")).contains("SIGSEGV"));
    QCOMPARE(csv_rows(dir.filePath("out/summary.csv"))[2].mid(0, 2), (QStringList{"boom", "failed"}));
  }

  void stopped_or_killed_parallel_run_resumes_identically_data() {
    QTest::addColumn<int>("sig");
    QTest::addColumn<double>("at");
    QTest::addColumn<bool>("isolate");
    QTest::newRow("SIGINT early") << int(SIGINT) << 0.2 << false;
    QTest::newRow("SIGTERM mid-queue") << int(SIGTERM) << 0.5 << false;
    QTest::newRow("SIGKILL mid-queue") << int(SIGKILL) << 0.4 << false;
    QTest::newRow("SIGKILL late") << int(SIGKILL) << 0.8 << false;
    QTest::newRow("--isolate, SIGINT mid-queue") << int(SIGINT) << 0.5 << true;
  }
  void stopped_or_killed_parallel_run_resumes_identically() {
    QFETCH(int, sig);
    QFETCH(double, at);
    QFETCH(bool, isolate);
    QTemporaryDir dir;
    // Six tests of about a second each on one thread, two at a time.
    write(dir.filePath("q.json"), small_queue(6, 40, 100));
    QElapsedTimer clock;
    clock.start();
    CliResult r = run_salsa({"run", "q.json", "--out", "reference", "--jobs", "2", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const qint64 whole_ms = clock.elapsed();
    {
      QStringList args{"run", "q.json", "--out", "out", "--jobs", "2", "-q"};
      if (isolate) args << "--isolate";
      QProcess run;
      QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
      env.remove("SALSA_PLUGIN_PATH");
      run.setProcessEnvironment(env);
      run.setWorkingDirectory(dir.path());
      run.start(salsa_executable(), args);
      QVERIFY(run.waitForStarted(30000));
      QVERIFY(wait_for(dir.filePath("out/.t0.partial/summary.csv")));
      QThread::msleep(static_cast<unsigned long>(at * static_cast<double>(whole_ms)));
      ::kill(static_cast<pid_t>(run.processId()), sig);
      run.waitForFinished(120000);
      const QString err = QString::fromUtf8(run.readAllStandardError());
      if (sig == SIGKILL) {
        QVERIFY(run.exitStatus() != QProcess::NormalExit || run.exitCode() == 0);  // 0: it had finished already
      } else if (run.exitCode() != 0) {  // 0: it had finished already
        QVERIFY2(run.exitCode() == 128 + sig && non_empty_lines(err).size() == 1 && err.contains("--resume"), qPrintable(err));
      }
    }
    // The queue's state so far: every test ok or missing (an interrupted test is not a failed one).
    r = run_salsa({"summarize", "out", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto rows = csv_rows(dir.filePath("out/summary.csv"));
    QCOMPARE(rows.size(), 7);
    for (int k = 1; k <= 6; ++k) {
      QCOMPARE(rows[k][0], QString("t%1").arg(k - 1));
      QVERIFY2(rows[k][1] == "ok" || rows[k][1] == "missing", qPrintable(rows[k].join(',')));
      QCOMPARE(rows[k][1] == "ok", QFileInfo::exists(dir.filePath(QString("out/t%1/config.json").arg(k - 1))));
    }
    r = run_salsa({"run", "q.json", "--out", "out", "--jobs", "2", "--resume", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    QCOMPARE(results_snapshot(dir.filePath("out")), results_snapshot(dir.filePath("reference")));
  }

  void another_queue_is_refused() {
    QTemporaryDir dir;
    write(dir.filePath("a.json"), small_queue(2, 1));
    write(dir.filePath("b.json"), R"([{"name": "other", "behavior": "flocking", "drones": 3, "time": 1}])");
    CliResult r = run_salsa({"run", "a.json", "--out", "out", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto before = snapshot(dir.filePath("out"));
    r = run_salsa({"run", "b.json", "--out", "out", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.err.contains("out/queue.json: holds the results of another queue"),
             describe(r));
    QCOMPARE(snapshot(dir.filePath("out")), before);
    // The same queue with another seed is another queue too.
    r = run_salsa({"run", "a.json", "--out", "out", "--seed", "9", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 2 && r.err.contains("out/queue.json: holds the same tests with other settings"), describe(r));
    r = run_salsa({"run", "b.json", "--out", "out", "--force", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(read_file(dir.filePath("out/queue.json")).contains("\"other\""));
    QCOMPARE(csv_rows(dir.filePath("out/summary.csv")).size(), 2);  // header and "other"
  }

  void summary_columns() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), R"([
      {"name": "plain", "behavior": "flocking", "drones": 5, "time": 1, "targets": {"count": 3}, "seed": 4, "metrics": []},
      {"name": "tuned", "behavior": {"name": "flocking", "params": {"cohesion_weight": 2}}, "drones": 5, "time": 1, "targets": {"count": 3}, "seed": 4, "metrics": []},
      {"name": "walk", "behavior": "random_walk", "drones": 5, "time": 1, "targets": {"count": 3}, "seed": 4, "metrics": []},
      {"name": "more", "behavior": "flocking", "drones": 6, "time": 1, "targets": {"count": 3}, "seed": 4, "metrics": []}])");
    CliResult r = run_salsa({"run", "q.json", "--out", "out", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto rows = csv_rows(dir.filePath("out/summary.csv"));
    QCOMPARE(rows.size(), 5);
    const QStringList header = rows[0];
    QCOMPARE(header.mid(0, 15), (QStringList{"name", "status", "error", "cell", "variant", "condition", "condition_label", "behavior",
                                              "repeat", "seed", "drones", "targets", "target", "map", "time"}));
    // Wall times are in OUT/timing.csv, so identical runs write identical summary.csv files.
    QVERIFY(!header.contains("wall_seconds"));
    const auto timing = csv_rows(dir.filePath("out/timing.csv"));
    QCOMPARE(timing.size(), 5);
    QCOMPARE(timing[0], (QStringList{"name", "wall_seconds"}));
    QCOMPARE(timing[1][0], QString("plain"));
    QVERIFY(timing[1][1].toDouble() > 0);
    for (const char* c : {"behavior.cohesion_weight", "behavior.turn_distance", "map.size", "drone.max_speed", "versions.behavior", "dt"})
      QVERIFY2(header.contains(c), c);
    QVERIFY(header.indexOf("behavior.cohesion_weight") < header.indexOf("map.size"));
    QVERIFY(header.indexOf("map.size") < header.indexOf("drone.max_speed"));
    QVERIFY(header.indexOf("drone.max_speed") < header.indexOf("versions.behavior"));
    auto at = [&](int row, const char* column) { return rows[row][header.indexOf(column)]; };
    QCOMPARE(at(1, "variant"), QString("flocking (defaults)"));
    QCOMPARE(at(2, "variant"), QString("flocking: cohesion_weight = 2"));
    QCOMPARE(at(3, "variant"), QString("random_walk (defaults)"));
    QCOMPARE(at(1, "condition"), QString());  // a queue without conditions
    QCOMPARE(at(1, "seed"), QString("4"));
    QCOMPARE(at(1, "drones"), QString("5"));
    QCOMPARE(at(1, "targets"), QString("3"));
    // The version and the first 12 hex digits of the plugin file's SHA-256: two builds of one version differ.
    QVERIFY2(QRegularExpression("^flocking 0\\.1\\.0 #[0-9a-f]{12}$").match(at(1, "versions.behavior")).hasMatch(),
             qPrintable(at(1, "versions.behavior")));
    // The cell: the condition apart from the behavior.
    QVERIFY(at(1, "cell").size() == 12);
    QCOMPARE(at(2, "cell"), at(1, "cell"));
    QCOMPARE(at(3, "cell"), at(1, "cell"));
    QVERIFY(at(4, "cell") != at(1, "cell"));
    // salsa summarize writes the same file from the folders alone.
    const QByteArray written = read_file(dir.filePath("out/summary.csv"));
    QVERIFY(QFile::remove(dir.filePath("out/summary.csv")));
    r = run_salsa({"summarize", "out", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(read_file(dir.filePath("out/summary.csv")), written);
    // outcome.csv's final values (written by the run when metrics are on) join the row; a column
    // named like an input is prefixed.
    write(dir.filePath("out/plain/outcome.csv"), "targets,targets_found,fraction_found,coverage\n3,1,0.333333,0.5\n");
    // Edited by hand: without its manifest it counts as a folder from before manifests (data present).
    QVERIFY(QFile::remove(dir.filePath("out/plain/manifest.json")));
    r = run_salsa({"summarize", "out", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto with_outcome = csv_rows(dir.filePath("out/summary.csv"));
    const QStringList h = with_outcome[0];
    QCOMPARE(h.mid(h.size() - 4), (QStringList{"outcome.targets", "targets_found", "fraction_found", "coverage"}));
    QCOMPARE(with_outcome[1].mid(h.size() - 4, 4), (QStringList{"3", "1", "0.333333", "0.5"}));
    QCOMPARE(with_outcome[2][h.indexOf("outcome.targets")], QString("3"));  // its own outcome.csv, without coverage
    QCOMPARE(with_outcome[2][h.indexOf("coverage")], QString());
  }

  // A queue with conditions, run for real: summary.csv names each test's condition in words; one cell
  // holds every condition (what a condition sets is not the cell), so comparison.csv compares within
  // each and did.csv across them, by world (a change at 1 s keeps the worlds) or by repeat (a larger
  // swarm has its own).
  void conditions_summary_comparison_did() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), R"({"repeats": 2, "reference": "random_walk",
      "base": {"drones": 5, "time": 2, "targets": {"count": 20}, "metrics": []},
      "sweep": {"behaviors": ["random_walk", "flocking"]},
      "conditions": [{"name": "baseline"}, {"name": "dropout", "changes": [{"time": 1, "set": {"drones": 3}}]}, {"name": "big", "drones": 7}]})");
    const CliResult r = run_salsa({"run", "q.json", "--out", "out", "-q", "--no-plots", "--no-drones-csv"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto rows = csv_rows(dir.filePath("out/summary.csv"));
    QCOMPARE(rows.size(), 1 + 2 * 3 * 2);
    const QStringList header = rows[0];
    std::map<QString, QStringList> by_name;
    for (qsizetype i = 1; i < rows.size(); ++i) by_name[rows[i][0]] = rows[i];
    auto at = [&](const char* name, const char* column) { return by_name[name].value(header.indexOf(column)); };
    QCOMPARE(at("flocking_dropout_r1", "condition"), QString("dropout"));
    QCOMPARE(at("flocking_dropout_r1", "condition_label"), QString("drones → 3 at 1 s"));
    QCOMPARE(at("flocking_big_r1", "condition_label"), QString("drones = 7"));
    QCOMPARE(at("random_walk_baseline_r0", "condition_label"), QString("no change"));
    QCOMPARE(at("random_walk_baseline_r0", "variant"), QString("random_walk (defaults)"));
    QCOMPARE(at("flocking_big_r0", "drones"), QString("7"));
    for (const char* name : {"flocking_dropout_r0", "random_walk_big_r1", "flocking_baseline_r1"})
      QCOMPARE(at(name, "cell"), at("random_walk_baseline_r0", "cell"));
    QCOMPARE(at("flocking_dropout_r0", "seed"), at("random_walk_baseline_r0", "seed"));
    QVERIFY(at("flocking_big_r0", "seed") != at("random_walk_baseline_r0", "seed"));
    // Within each condition: flocking against the reference.
    const auto comparison = csv_rows(dir.filePath("out/comparison.csv"));
    QCOMPARE(comparison.size(), 1 + 3);
    for (qsizetype i = 1; i < comparison.size(); ++i) {
      QCOMPARE(comparison[i].mid(8, 3), (QStringList{"flocking (defaults)", "random_walk (defaults)", "2"}));
      QCOMPARE(comparison[i][1], (QStringList{"baseline", "dropout", "big"})[i - 1]);
    }
    // Across them: both conditions against the baseline, 2 repeats each.
    const auto did = csv_rows(dir.filePath("out/did.csv"));
    QCOMPARE(did.size(), 1 + 2);
    QCOMPARE(did[1].mid(7, 5), (QStringList{"flocking (defaults)", "random_walk (defaults)", "baseline", "dropout", "2"}));
    QCOMPARE(did[2].mid(9, 3), (QStringList{"baseline", "big", "2"}));
    // did = diff_condition − diff_baseline, the two means of comparison.csv.
    QVERIFY(std::abs(did[1][14].toDouble() - (comparison[2][13].toDouble() - comparison[1][13].toDouble())) < 1e-5);
    // Each variant under each condition against itself under the baseline: 2 conditions × 2 variants,
    // in the baseline's order; the difference is the two means' (comparison.csv's mean_a under each).
    const auto effects = csv_rows(dir.filePath("out/condition_effects.csv"));
    QCOMPARE(effects.size(), 1 + 4);
    QCOMPARE(effects[1].mid(7, 4), (QStringList{"random_walk (defaults)", "baseline", "dropout", "2"}));
    QCOMPARE(effects[2].mid(7, 4), (QStringList{"flocking (defaults)", "baseline", "dropout", "2"}));
    QCOMPARE(effects[4].mid(7, 4), (QStringList{"flocking (defaults)", "baseline", "big", "2"}));
    QVERIFY(std::abs(effects[2][15].toDouble() - (comparison[2][11].toDouble() - comparison[1][11].toDouble())) < 1e-5);
    QVERIFY(std::abs(effects[2][11].toDouble() - comparison[1][11].toDouble()) < 1e-5);
  }

  // Test folders summarized without their queue.json (the docs' recipe for a subset: copy the folders
  // into a new one): the baseline condition and the reference are the queue's, not the folders', so
  // summarize says in one line what it took instead (here the baseline condition 'windy' is last in
  // folder order, and the reference 'flocking' is not the first variant either).
  void summarize_without_queue_json_says_what_it_assumed() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), R"({"repeats": 2, "reference": "flocking",
      "base": {"drones": 5, "time": 2, "targets": {"count": 20}, "metrics": []},
      "sweep": {"behaviors": ["random_walk", "flocking"]},
      "conditions": [{"name": "windy", "drones": 3}, {"name": "calm"}]})");
    CliResult r = run_salsa({"run", "q.json", "--out", "out", "-q", "--no-plots", "--no-drones-csv"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto did = csv_rows(dir.filePath("out/did.csv"));
    QCOMPARE(did.size(), 1 + 1);
    QCOMPARE(did[1].mid(7, 4), (QStringList{"random_walk (defaults)", "flocking (defaults)", "windy", "calm"}));
    // With queue.json, nothing is assumed.
    r = run_salsa({"summarize", "out", "-q", "--no-plots"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    QCOMPARE(csv_rows(dir.filePath("out/did.csv")), did);
    const fs::path sub = fs::path(dir.path().toStdString()) / "sub";
    fs::create_directory(sub);
    for (const auto& entry : fs::directory_iterator(fs::path(dir.path().toStdString()) / "out"))
      if (entry.is_directory()) fs::copy(entry.path(), sub / entry.path().filename(), fs::copy_options::recursive);
    r = run_salsa({"summarize", "sub", "-q", "--no-plots"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(non_empty_lines(r.err), (QStringList{"salsa: warning: summarize: sub has no queue.json: the baseline is condition 'calm' "
                                                  "(the first in folder order) and pairs are every two variants (no reference)"}));
    // What it says is what it wrote.
    const auto assumed = csv_rows(dir.filePath("sub/did.csv"));
    QCOMPARE(assumed.size(), 1 + 1);
    QCOMPARE(assumed[1].mid(7, 4), (QStringList{"flocking (defaults)", "random_walk (defaults)", "calm", "windy"}));
    // A folder whose tests have one condition and one variant has nothing to assume.
    fs::create_directory(sub.parent_path() / "one");
    for (const char* name : {"flocking_calm_r0", "flocking_calm_r1"})
      fs::copy(sub / name, sub.parent_path() / "one" / name, fs::copy_options::recursive);
    r = run_salsa({"summarize", "one", "-q", "--no-plots"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
  }

  // "top": comparison.csv pairs the 3 variants of each condition with the highest mean fraction_found
  // (ranked here from summary.csv; the two conditions rank them differently), each with the others,
  // the better first; queue.json records it, and a run of the same tests with another top is another queue.
  void top_compares_the_best_variants_within_each_condition() {
    QTemporaryDir dir;
    const QByteArray queue = R"({"repeats": 2, "top": 3,
      "base": {"drones": 5, "time": 20, "map": {"name": "empty", "params": {"size": 200}}, "targets": {"count": 400}, "metrics": []},
      "sweep": {"behaviors": ["random_walk", "pheromone_avoidance", "dynamic_space_partitioning", {"name": "flocking", "params": {"cohesion_weight": [1, 3]}}]},
      "conditions": [{"name": "five"}, {"name": "three", "drones": 3}]})";
    write(dir.filePath("q.json"), queue);
    CliResult r = run_salsa({"run", "q.json", "--out", "out", "-q", "--no-plots", "--no-drones-csv"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto rows = csv_rows(dir.filePath("out/summary.csv"));
    QCOMPARE(rows.size(), 1 + 5 * 2 * 2);
    const qsizetype c_variant = rows[0].indexOf("variant"), c_condition = rows[0].indexOf("condition"), c_found = rows[0].indexOf("fraction_found");
    QVERIFY(c_variant >= 0 && c_condition >= 0 && c_found >= 0);
    // Variant labels hold no comma here ("flocking: cohesion_weight = 3"), so splitting on ',' is safe.
    QStringList expected;
    for (const QString condition : {"five", "three"}) {
      QStringList order;  // first appearance
      std::map<QString, double> sum;
      for (qsizetype i = 1; i < rows.size(); ++i)
        if (rows[i][c_condition] == condition) {
          if (!sum.count(rows[i][c_variant])) order << rows[i][c_variant];
          sum[rows[i][c_variant]] += rows[i][c_found].toDouble();
        }
      QCOMPARE(order.size(), 5);
      std::stable_sort(order.begin(), order.end(), [&](const QString& a, const QString& b) { return sum[a] > sum[b]; });
      QVERIFY2(sum[order[2]] > sum[order[3]], "the 3rd and 4th tie: the queue does not tell which pairs top 3 picks");
      for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b) expected << condition + ":" + order[a] + "|" + order[b];
    }
    QStringList pairs;
    for (const QStringList& row : csv_rows(dir.filePath("out/comparison.csv")).mid(1)) pairs << row[1] + ":" + row[8] + "|" + row[9];
    QCOMPARE(pairs, expected);
    const QString record = QString::fromUtf8(read_file(dir.filePath("out/queue.json")));
    QVERIFY2(record.contains("\"top\": 3\n"), qPrintable(record));
    write(dir.filePath("q2.json"), QByteArray(queue).replace("\"top\": 3", "\"top\": 2"));
    r = run_salsa({"run", "q2.json", "--out", "out", "-q", "--no-plots", "--no-drones-csv"}, dir.path());
    QVERIFY2(r.exit_code == 2 && r.err.contains("out/queue.json: holds the same tests with other settings"), describe(r));
  }

  // Re-pairing without rerunning: `salsa plot OUT --reference V` (or --top K) writes the comparison a run
  // of the queue with that reference (top) in its file writes, byte for byte, and leaves queue.json as it
  // is (a later `salsa plot OUT` is the queue's own again); a bad V or K is refused in one line naming
  // the option, the folder untouched. The conditions differ in one number (comm.range): ranking.png and
  // by_comm.range.png are drawn.
  void plot_re_pairs_as_a_run_with_that_reference() {
    QTemporaryDir dir;
    const QByteArray queue = R"({"repeats": 2, "reference": "random_walk",
      "base": {"drones": 5, "time": 20, "map": {"name": "empty", "params": {"size": 200}}, "targets": {"count": 400}, "metrics": [], "comm": {"range": 50}},
      "sweep": {"behaviors": ["random_walk", "flocking", "pheromone_avoidance"]},
      "conditions": [{"name": "r50"}, {"name": "r100", "set": {"comm.range": 100}}]})";
    write(dir.filePath("q.json"), queue);
    write(dir.filePath("q_flocking.json"), QByteArray(queue).replace("\"reference\": \"random_walk\"", "\"reference\": \"flocking\""));
    write(dir.filePath("q_top.json"), QByteArray(queue).replace("\"reference\": \"random_walk\"", "\"top\": 2"));
    for (const auto& [file, out] : {std::pair{"q.json", "out"}, {"q_flocking.json", "flocking"}, {"q_top.json", "top"}}) {
      QStringList args{"run", file, "--out", out, "-q", "--no-drones-csv"};
      if (QString(out) != "out") args << "--no-plots";
      const CliResult r = run_salsa(args, dir.path());
      QVERIFY2(r.exit_code == 0, describe(r));
    }
    for (const char* png : {"ranking.png", "by_comm.range.png"}) QVERIFY2(QFileInfo::exists(dir.filePath("out/plots/") + png), png);
    const QStringList tables{"comparison.csv", "did.csv", "condition_effects.csv", "ranking.csv"};
    auto files = [&](const QString& out) {
      QStringList texts;
      for (const QString& t : tables) texts << QString::fromUtf8(read_file(dir.filePath(out + "/" + t)));
      return texts;
    };
    const QStringList own = files("out");
    QVERIFY(own != files("flocking"));
    QCOMPARE(own[3], files("flocking")[3]);  // the ranking does not depend on the pairs
    const auto before = snapshot(dir.filePath("out"));
    const std::vector<std::pair<QStringList, QString>> bad{
        {{"--reference", "nope"}, "--reference: 'nope' names no variant of out (allowed: random_walk (defaults); flocking (defaults); "
                                  "pheromone_avoidance (defaults); or a behavior's name for its defaults)"},
        {{"--top", "1"}, "--top: 1 is out of range (allowed: a whole number from 2 to 3, the variants of out)"},
        {{"--top", "4"}, "--top: 4 is out of range (allowed: a whole number from 2 to 3, the variants of out)"},
        {{"--top", "two"}, "--top: 'two' is not a whole number (allowed: a whole number from 2 to 3, the variants of out)"},
        {{"--top", "2", "--reference", "flocking"}, "--top: given with --reference (allowed: one of them"},
        {{"--reference", "flocking", "--out", "x.png"}, "--out: x.png: not for a folder"}};
    for (const auto& [args, expect] : bad) {
      const CliResult r = run_salsa(QStringList{"plot", "out"} + args, dir.path());
      QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.err.contains(expect), describe(r));
      QCOMPARE(snapshot(dir.filePath("out")), before);
    }
    for (const QString folder : {"out/random_walk_r50_r0", "out/summary.csv"}) {  // a test's folder, a file: no pairs to choose
      const CliResult r = run_salsa({"plot", folder, "--top", "2"}, dir.path());
      const QString expect = "--top: " + folder + " is not a queue's folder (allowed: a folder 'salsa run' wrote a queue's summary.csv into)";
      QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.err.contains(expect), describe(r));
      QCOMPARE(snapshot(dir.filePath("out")), before);
    }
    CliResult r = run_salsa({"plot", "out", "--reference", "flocking"}, dir.path());  // a behavior's name for its defaults, as in the file
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(files("out"), files("flocking"));
    QCOMPARE(read_file(dir.filePath("out/queue.json")), before.value("queue.json"));
    r = run_salsa({"plot", "out", "--top", "2"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(files("out"), files("top"));
    r = run_salsa({"plot", "out"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(files("out"), own);
  }

  void shards_cover_the_queue_once() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue(10, 1));
    CliResult r = run_salsa({"run", "q.json", "--out", "whole", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QStringList ran;
    for (int i = 0; i < 3; ++i) {
      r = run_salsa({"run", "q.json", "--out", "out", "--shard", QString("%1/3").arg(i)}, dir.path());
      QVERIFY2(r.exit_code == 0 && r.out.contains("'salsa summarize out'"), describe(r));
      for (const QString& line : non_empty_lines(r.out))
        if (line.startsWith('[')) ran << line.section(' ', 1, 1).chopped(1);
      QVERIFY(!QFileInfo::exists(dir.filePath("out/summary.csv")));  // a shard is not the whole queue
    }
    ran.sort();
    QStringList all;
    for (int k = 0; k < 10; ++k) all << QString("t%1").arg(k);
    all.sort();
    QCOMPARE(ran, all);  // no overlap, no gap
    r = run_salsa({"summarize", "out", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(results_snapshot(dir.filePath("out")), results_snapshot(dir.filePath("whole")));
  }

  void slurm_array_picks_the_shard_data() {
    QTest::addColumn<QString>("id");
    QTest::addColumn<QString>("min");
    QTest::addColumn<QStringList>("expect");
    QTest::newRow("ids from 0") << "1" << "0" << QStringList{"t1", "t4"};
    QTest::newRow("ids from 1") << "1" << "1" << QStringList{"t0", "t3"};
    QTest::newRow("ids from 10") << "12" << "10" << QStringList{"t2", "t5"};
  }
  void slurm_array_picks_the_shard() {
    QFETCH(QString, id);
    QFETCH(QString, min);
    QFETCH(QStringList, expect);
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue(6, 1));
    const CliResult r = run_program(salsa_executable(), {"run", "q.json", "--out", "out"}, dir.path(),
                                     {{"SLURM_ARRAY_TASK_ID", id}, {"SLURM_ARRAY_TASK_MIN", min}, {"SLURM_ARRAY_TASK_COUNT", "3"}});
    QVERIFY2(r.exit_code == 0, describe(r));
    QStringList ran;
    for (const QString& name : QDir(dir.filePath("out")).entryList(QDir::Dirs | QDir::NoDotAndDotDot)) ran << name;
    QCOMPARE(ran, expect);
  }

  void bad_options_data() {
    QTest::addColumn<QStringList>("args");
    QTest::addColumn<QString>("expect");
    QTest::newRow("jobs -1") << QStringList{"--jobs", "-1"} << "--jobs: \"-1\" is not a whole number (allowed: a whole number in [0, 1024]";
    QTest::newRow("jobs 2000") << QStringList{"--jobs", "2000"} << "--jobs: 2000 is out of range";
    QTest::newRow("shard 3/3") << QStringList{"--shard", "3/3"} << "--shard: \"3/3\" is not a shard of the queue (allowed: i/n";
    QTest::newRow("shard 1") << QStringList{"--shard", "1"} << "--shard: \"1\" is not a shard";
    QTest::newRow("shard 0/0") << QStringList{"--shard", "0/0"} << "--shard: \"0/0\" is not a shard";
    QTest::newRow("shard /2") << QStringList{"--shard", "/2"} << "--shard: \"/2\" is not a shard";
  }
  void bad_options() {
    QFETCH(QStringList, args);
    QFETCH(QString, expect);
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "x", "behavior": "flocking", "drones": 3, "time": 1})");
    const auto before = snapshot(dir.path());
    const CliResult r = run_salsa(QStringList{"run", "t.json"} + args, dir.path());
    QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.err.contains(expect), describe(r));
    QCOMPARE(snapshot(dir.path()), before);
  }

  void mpi_ranks_run_each_test_once() {
    QTemporaryDir dir;
    write(dir.filePath("q.json"), small_queue(12, 2));
    CliResult r = run_salsa({"run", "q.json", "--out", "one", "--jobs", "1", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto mpi = run_mpi(3, {"run", "q.json", "--out", "D"}, dir.path());
    if (!mpi) QSKIP("mpirun is not installed (Debian: openmpi-bin)");
    r = *mpi;
    if (r.err.contains("built without MPI")) QSKIP("this salsa was built without MPI");
    QVERIFY2(r.exit_code == 0, describe(r));
    // Each test exactly once: one progress line each, over all ranks.
    for (int k = 0; k < 12; ++k) QVERIFY2(r.out.count(QString("] t%1: ").arg(k)) == 1, describe(r));
    const auto rows = csv_rows(dir.filePath("D/summary.csv"));
    QCOMPARE(rows.size(), 13);
    for (int k = 1; k <= 12; ++k) QCOMPARE(rows[k][1], QString("ok"));
    QCOMPARE(results_snapshot(dir.filePath("D")), results_snapshot(dir.filePath("one")));
    // --isolate on every rank: rank 0 holds the output folder's lock for the other ranks' children too.
    r = *run_mpi(3, {"run", "q.json", "--out", "I", "--isolate", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    QCOMPARE(results_snapshot(dir.filePath("I")), results_snapshot(dir.filePath("one")));
  }
};

QTEST_GUILESS_MAIN(TestQueueRun)
#include "test_queue_run.moc"
