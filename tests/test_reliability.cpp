// What a run promises about its data, proven with the real `salsa` CLI: it touches only folders it
// wrote, rows reach the disk within 2 s whatever the log interval, config.json reruns its test
// exactly, --resume keeps only identical tests, a crashing plugin is named (and with --isolate fails
// only its test), and a run killed, interrupted or stopped by a full disk resumes to byte-identical
// results (docs/output-format.md).
#include <sys/mount.h>
#include <unistd.h>

#include <QElapsedTimer>
#include <QScopeGuard>
#include <QThread>

#include <csignal>

#include "common.hpp"

using namespace salsa_test;

namespace {

QString crash_plugins() { return q(test_plugins_dir() / "crash"); }

/// A salsa process started in the background (same clean environment as run_salsa), to be signalled.
struct Background {
  QProcess process;
  Background(const QStringList& args, const QString& dir) {
    static QTemporaryDir home;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.remove("SALSA_PLUGIN_PATH");
    env.insert("HOME", home.path());
    process.setProcessEnvironment(env);
    process.setWorkingDirectory(dir);
    process.start(salsa_executable(), args);
    process.waitForStarted(30000);
  }
  void signal(int sig) { ::kill(static_cast<pid_t>(process.processId()), sig); }
  CliResult finish() {
    process.waitForFinished(120000);
    CliResult r;
    r.crashed = process.exitStatus() != QProcess::NormalExit;
    r.exit_code = process.exitCode();
    r.out = QString::fromUtf8(process.readAllStandardOutput());
    r.err = QString::fromUtf8(process.readAllStandardError());
    return r;
  }
};

/// Waits until `file` exists (a run has reached that point); false after 60 s.
bool wait_for(const QString& file) {
  for (int i = 0; i < 6000; ++i) {
    if (QFileInfo::exists(file)) return true;
    QThread::msleep(10);
  }
  return false;
}

/// Every line of every test's CSV under `dir` is whole: ends in a newline and has the header's field
/// count. (The queue's own files, at the top, are written whole at the end and may quote commas.)
/// After a SIGKILL (`killed`), a file in a `.partial` folder may end in the start of a row: the kernel
/// stops a write() part way when the process is killed, so no writer can promise more. Every line
/// before it is whole, and --resume redoes that test.
void check_whole_rows(const QString& dir, bool killed = false) {
  const auto files = snapshot(dir);
  for (auto it = files.begin(); it != files.end(); ++it) {
    if (!it.key().endsWith(".csv") || !it.key().contains('/')) continue;
    const QByteArray& text = it.value();
    const bool may_be_cut = killed && it.key().contains(".partial/");
    QVERIFY2(text.isEmpty() || text.endsWith('\n') || may_be_cut, qPrintable(it.key() + " ends in half a row"));
    const QList<QByteArray> lines = text.split('\n');
    const auto commas = lines.front().count(',');
    for (qsizetype i = 0; i + 1 < lines.size(); ++i)
      QVERIFY2(lines[i].count(',') == commas, qPrintable(it.key() + ": line " + QString::number(i + 1) + " is not a whole row"));
    QVERIFY2(lines.back().count(',') <= commas, qPrintable(it.key() + ": its last line is longer than a row"));
  }
}

void write(const QString& path, const QByteArray& text) { QVERIFY(write_file(path, text)); }

// A queue of three tests, long enough (a few seconds on one thread) to be interrupted mid-test and
// mid-write: drones.csv is written all the time.
const QByteArray queue = R"([
  {"name": "a", "behavior": "flocking", "drones": 150, "time": 30, "log_interval": 0.05, "targets": {"count": 20}},
  {"name": "b", "behavior": "random_walk", "drones": 150, "time": 30, "log_interval": 0.05, "targets": {"count": 20}},
  {"name": "c", "behavior": "flocking", "drones": 100, "time": 30, "log_interval": 0.05, "seed": 7}
])";

}  // namespace

class TestReliability : public QObject {
  Q_OBJECT

  QTemporaryDir reference_dir_;  // the queue run once, uninterrupted
  qint64 reference_ms_ = 0;      // and how long that took
  QString reference() const { return reference_dir_.filePath("out"); }

 private Q_SLOTS:
  void initTestCase() {
    write(reference_dir_.filePath("queue.json"), queue);
    QElapsedTimer clock;
    clock.start();
    const CliResult r = run_salsa({"run", "queue.json", "--out", "out", "--threads", "1", "-q"}, reference_dir_.path());
    QVERIFY2(r.exit_code == 0 && !r.crashed, describe(r));
    reference_ms_ = clock.elapsed();
    for (const char* name : {"a", "b", "c"}) QVERIFY(QFileInfo::exists(reference() + "/" + name + "/config.json"));
  }

  // ---- Item 1: only folders salsa wrote are removed or replaced.

  void force_never_follows_a_stem_out_of_out() {
    for (const QString file : {"..json", "...json"}) {
      QTemporaryDir dir;
      write(dir.filePath("out/keep/data.txt"), "mine\n");
      write(dir.filePath("keep.txt"), "mine too\n");
      write(dir.filePath(file), R"({"behavior": "flocking", "drones": 3, "time": 1})");
      const auto before = snapshot(dir.path());
      const CliResult r = run_salsa({"run", file, "--out", "out", "--force"}, dir.path());
      QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1, describe(r));
      QCOMPARE(snapshot(dir.path()), before);
    }
  }

  void force_replaces_only_marked_folders() {
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "x", "behavior": "flocking", "drones": 3, "time": 1})");
    write(dir.filePath("out/x/config.json"), "{\"mine\": true}\n");
    write(dir.filePath("out/x/notes.txt"), "my notes\n");
    auto before = snapshot(dir.path());
    CliResult r = run_salsa({"run", "t.json", "--out", "out", "--force"}, dir.path());
    QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.err.contains("out/x") && r.err.contains(".salsa-test"),
             describe(r));
    QCOMPARE(snapshot(dir.path()), before);
    // The same with --resume: a finished test of another kind there is not salsa's to judge either.
    r = run_salsa({"run", "t.json", "--out", "out", "--force", "--resume"}, dir.path());
    QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1, describe(r));
    QCOMPARE(snapshot(dir.path()), before);

    // A symbolic link to a folder salsa wrote is not a folder salsa wrote inside OUT.
    QTemporaryDir other;
    r = run_salsa({"run", "t.json", "--out", other.filePath("real")}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(QDir().mkpath(dir.filePath("out2")) && QFile::link(other.filePath("real/x"), dir.filePath("out2/x")));
    const auto outside = snapshot(other.path());
    r = run_salsa({"run", "t.json", "--out", "out2", "--force"}, dir.path());
    QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1, describe(r));
    QCOMPARE(snapshot(other.path()), outside);

    // A folder salsa wrote is replaced (by another test: its own seed).
    write(dir.filePath("t.json"), R"({"name": "x", "behavior": "flocking", "drones": 3, "time": 1, "seed": 5})");
    r = run_salsa({"run", "t.json", "--out", other.filePath("real"), "--force"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(read_file(other.filePath("real/x/config.json")).contains("\"seed\": 5"));
  }

  void out_must_be_a_folder() {
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "x", "behavior": "flocking", "drones": 3, "time": 1})");
    write(dir.filePath("file.txt"), "a file\n");
    const auto before = snapshot(dir.path());
    for (const QString out : {"file.txt", "file.txt/sub", ""}) {
      const CliResult r = run_salsa({"run", "t.json", "--out", out}, dir.path());
      QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.err.contains("--out"), describe(r));
      QCOMPARE(snapshot(dir.path()), before);
    }
  }

  void leftover_partial_is_cleaned_up_only_when_salsa_wrote_it() {
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "x", "behavior": "flocking", "drones": 3, "time": 1})");
    // Not salsa's: left alone.
    write(dir.filePath("out/.x.partial/precious.txt"), "mine\n");
    const auto before = snapshot(dir.path());
    CliResult r = run_salsa({"run", "t.json", "--out", "out"}, dir.path());
    QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.err.contains(".x.partial"), describe(r));
    QCOMPARE(snapshot(dir.path()), before);
    // salsa's (marked): cleaned up by the next run.
    QVERIFY(QFile::remove(dir.filePath("out/.x.partial/precious.txt")));
    write(dir.filePath("out/.x.partial/.salsa-test"), "salsa\n");
    write(dir.filePath("out/.x.partial/summary.csv"), "time,targets_found\n0.0000,0\n0.5");
    r = run_salsa({"run", "t.json", "--out", "out"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(!QFileInfo::exists(dir.filePath("out/.x.partial")));
    QVERIFY(QFileInfo::exists(dir.filePath("out/x/.salsa-test")));
  }

  // ---- Item 8: rows on disk within 2 s whatever the log interval.

  void rows_reach_the_disk_within_two_seconds() {
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "slow", "behavior": "flocking", "drones": 50, "time": 1000000, "log_interval": 10000})");
    Background run({"run", "t.json", "--out", "out", "--threads", "1"}, dir.path());
    QVERIFY(wait_for(dir.filePath("out/.slow.partial/summary.csv")));
    QThread::msleep(3000);
    run.signal(SIGKILL);
    run.finish();
    const QStringList summary = non_empty_lines(QString::fromUtf8(read_file(dir.filePath("out/.slow.partial/summary.csv"))));
    QVERIFY2(summary.size() >= 2 && summary[1].startsWith("0.0000,"), qPrintable(summary.join('\n')));
    // The header, then whole logged steps of 50 drones (the t = 0 one at least).
    const QStringList drones = non_empty_lines(QString::fromUtf8(read_file(dir.filePath("out/.slow.partial/drones.csv"))));
    QVERIFY2(drones.size() >= 1 + 50 && (drones.size() - 1) % 50 == 0, qPrintable(QString::number(drones.size()) + " lines"));
    check_whole_rows(dir.filePath("out/.slow.partial"));
  }

  // A stop is honoured within a second whatever one step costs: here a step takes several seconds
  // (20,000 flocking drones that all see each other). The process ends with 128 + SIGTERM, names the
  // test, its step and its .partial folder, publishes nothing, and --resume then redoes the test.
  void sigterm_stops_a_slow_step_within_a_second() {
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "slow", "behavior": "flocking", "drones": 20000, "drone": {"detection_range": 5000},
                                      "map": {"name": "empty", "params": {"size": 2000}}, "time": 600})");
    Background run({"run", "t.json", "--out", "out", "--threads", "1", "-q"}, dir.path());
    QVERIFY(wait_for(dir.filePath("out/.slow.partial/summary.csv")));
    QThread::msleep(1500);  // well into a step
    QElapsedTimer timer;
    timer.start();
    run.signal(SIGTERM);
    const CliResult r = run.finish();
    const auto ms = timer.elapsed();
    qInfo("stopped %lld ms after SIGTERM", static_cast<long long>(ms));
    QVERIFY2(!r.crashed && r.exit_code == 128 + SIGTERM, describe(r));
    QVERIFY2(ms < 2000, qPrintable(QString::number(ms) + " ms"));
    QVERIFY2(non_empty_lines(r.err).size() == 1 && r.err.contains("test 'slow' (t.json) stopped by SIGTERM (terminated) at step ") &&
                 r.err.contains("rows so far in out/.slow.partial"),
             describe(r));
    QVERIFY(!QFileInfo::exists(dir.filePath("out/slow")));  // nothing published
    check_whole_rows(dir.filePath("out/.slow.partial"));
    // The folder is as an interrupted run leaves it: --resume takes it (here with a short test).
    write(dir.filePath("t.json"), R"({"name": "slow", "behavior": "flocking", "drones": 5, "time": 1})");
    const CliResult again = run_salsa({"run", "t.json", "--out", "out", "--resume", "-q"}, dir.path());
    QVERIFY2(again.exit_code == 0 && QFileInfo::exists(dir.filePath("out/slow/summary.csv")), describe(again));
  }

  // ---- Item 9: config.json reruns exactly; --resume keeps only identical tests; CLI values.

  void config_json_reruns_exactly() {
    QTemporaryDir dir;
    write(dir.filePath("maps/w.json"), read_file(q(source_dir() / "examples/maps/warehouse.json")));
    write(dir.filePath("tests/t.json"),
          R"({"name": "x", "behavior": "flocking", "drones": 20, "time": 5, "map": "../maps/w.json", "targets": {"count": 10}})");
    CliResult r = run_salsa({"run", "tests/t.json", "--out", "one", "--seed", "9007199254740992"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    // From another working folder, as a user rerunning an old result would.
    r = run_salsa({"run", dir.filePath("one/x/config.json"), "--out", dir.filePath("two")}, QDir::tempPath());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(results_snapshot(dir.filePath("two/x")), results_snapshot(dir.filePath("one/x")));
  }

  void resume_refuses_a_different_test() {
    QTemporaryDir dir;
    // Seeds given in the file: --seed would pair them (docs/test-format.md), and the message shows them as given.
    const QByteArray seed_3 = R"({"name": "x", "behavior": "flocking", "drones": 3, "time": 1, "seed": 3})";
    const QByteArray seed_4 = R"({"name": "x", "behavior": "flocking", "drones": 3, "time": 1, "seed": 4})";
    write(dir.filePath("t.json"), seed_3);
    CliResult r = run_salsa({"run", "t.json", "--out", "out"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    write(dir.filePath("t.json"), seed_4);
    const auto before = snapshot(dir.path());
    r = run_salsa({"run", "t.json", "--out", "out", "--resume"}, dir.path());
    QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1, describe(r));
    QVERIFY2(r.err.contains("out/x/config.json: seed is 3 there, 4 now; --resume keeps only identical tests (use --force to replace it)"),
             describe(r));
    QCOMPARE(snapshot(dir.path()), before);
    write(dir.filePath("t.json"), seed_3);
    const auto with_seed_3 = snapshot(dir.path());
    r = run_salsa({"run", "t.json", "--out", "out", "--time", "2", "--resume"}, dir.path());
    QVERIFY2(r.exit_code == 2 && r.err.contains("time is 1.0 there, 2.0 now"), describe(r));
    QCOMPARE(snapshot(dir.path()), with_seed_3);
    r = run_salsa({"run", "t.json", "--out", "out", "--resume"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.out.contains("skipped"), describe(r));
    QCOMPARE(results_snapshot_of(snapshot(dir.path()), "out/"), results_snapshot_of(with_seed_3, "out/"));  // plots redrawn
    write(dir.filePath("t.json"), seed_4);
    r = run_salsa({"run", "t.json", "--out", "out", "--resume", "--force"}, dir.path());
    QVERIFY2(r.exit_code == 0 && read_file(dir.filePath("out/x/config.json")).contains("\"seed\": 4"), describe(r));
  }

  void bad_cli_values_data() {
    QTest::addColumn<QStringList>("args");
    QTest::addColumn<QString>("expect");
    QTest::newRow("seed -1") << QStringList{"--seed", "-1"} << "--seed: \"-1\" is not a whole number (allowed: a whole number in [0, 9007199254740992])";
    QTest::newRow("seed 2^53+1") << QStringList{"--seed", "9007199254740993"} << "--seed: 9007199254740993 is out of range";
    QTest::newRow("seed 2^64") << QStringList{"--seed", "18446744073709551616"} << "--seed: 18446744073709551616 is out of range";
    QTest::newRow("seed 1.5") << QStringList{"--seed", "1.5"} << "--seed: \"1.5\" is not a whole number";
    QTest::newRow("threads -1") << QStringList{"--threads", "-1"} << "--threads: \"-1\" is not a whole number (allowed: a whole number in [0, 1024]";
    QTest::newRow("threads 5000") << QStringList{"--threads", "5000"} << "--threads: 5000 is out of range";
    QTest::newRow("time abc") << QStringList{"--time", "abc"} << "--time: \"abc\" is not a number";
    QTest::newRow("time 1e400") << QStringList{"--time", "1e400"} << "--time: 1e400 is out of range";
    QTest::newRow("time nan") << QStringList{"--time", "nan"} << "--time: nan is out of range";
    QTest::newRow("time 0") << QStringList{"--time", "0"} << "--time: 0 is out of range (allowed: [0.01666";
    QTest::newRow("log-interval -1") << QStringList{"--log-interval", "-1"} << "--log-interval: -1 is out of range";
    QTest::newRow("unknown option") << QStringList{"--frobnicate"} << "unrecognised option '--frobnicate'";
    QTest::newRow("missing value") << QStringList{"--seed"} << "the required argument for option '--seed' is missing";
    QTest::newRow("out file") << QStringList{"--out", "t.json"} << "--out: t.json is a file (allowed: a folder, created if missing)";
  }
  void bad_cli_values() {
    QFETCH(QStringList, args);
    QFETCH(QString, expect);
    QTemporaryDir dir;
    write(dir.filePath("t.json"), R"({"name": "x", "behavior": "flocking", "drones": 3, "time": 1})");
    const auto before = snapshot(dir.path());
    const CliResult r = run_salsa(QStringList{"run", "t.json"} + args, dir.path());
    QVERIFY2(r.exit_code == 2 && !r.crashed && non_empty_lines(r.err).size() == 1 && r.err.contains(expect), describe(r));
    QCOMPARE(snapshot(dir.path()), before);
  }

  // ---- Huge swarms: said so up front, not under --quiet.

  void huge_swarm_is_announced() {
    QTemporaryDir dir;
    write(dir.filePath("huge.json"), R"({"name": "huge", "behavior": "flocking", "drones": 1000000, "time": 60, "map": {"name": "empty", "params": {"size": 2000}}})");
    CliResult r = run_salsa({"validate", "huge.json"}, dir.path());
    QVERIFY2(r.exit_code == 0 && non_empty_lines(r.err).size() == 1 && r.err.startsWith("salsa: warning: huge.json: 1,000,000 drones") &&
                 r.err.contains("neighbours per drone"),
             describe(r));
    r = run_salsa({"validate", "huge.json", "--quiet"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
  }

  // ---- Item 7: crashing plugins are named; --isolate fails only their test.

  void crash_is_named_data() {
    QTest::addColumn<int>("mode");
    QTest::addColumn<QString>("what");
    QTest::newRow("segfault") << 1 << "died of SIGSEGV (segmentation fault) at step 30 of 120";
    QTest::newRow("std::exit") << 2 << "ended by a call to exit() in plugin code at step 30 of 120";
    QTest::newRow("abort") << 4 << "died of SIGABRT (aborted) at step 30 of 120";
  }
  void crash_is_named() {
    QFETCH(int, mode);
    QFETCH(QString, what);
    QTemporaryDir dir;
    write(dir.filePath("t.json"), QStringLiteral(R"({"name": "boom", "behavior": {"name": "test_crash", "params": {"mode": %1}}, "drones": 4, "time": 2})")
                                      .arg(mode)
                                      .toUtf8());
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--plugin-dir", crash_plugins()}, dir.path());
    QVERIFY2(mode == 2 ? r.exit_code == 1 && !r.crashed : r.crashed, describe(r));
    QVERIFY2(non_empty_lines(r.err).size() == 1, describe(r));
    QVERIFY2(r.err.startsWith("salsa: test 'boom' (t.json) " + what + "; plugins: behavior 'test_crash' (") &&
                 r.err.contains("libtest_crash.so)") && r.err.contains("rows so far in out/.boom.partial"),
             describe(r));
  }

  // ---- Every failure names its plugin: a plugin that throws, from any call site, fails its test on
  // one line naming the test, the plugin's kind, registered name and file, and the time; never another
  // plugin (a throwing contact handler or target kind was once blamed on the behavior).
  void every_failure_names_its_plugin_data() {
    QTest::addColumn<QByteArray>("test");
    QTest::addColumn<QString>("named");
    const QByteArray head = R"({"name": "b", "behavior": {"name": "blame_behavior", "params": {"throw_from": %1}}, "drones": 50, "time": 2, )";
    auto row = [&](const char* name, const QByteArray& rest, const char* named, int throw_from = -1) {
      QTest::newRow(name) << QByteArray(head).replace("%1", QByteArray::number(throw_from)) + rest + "}" << QString(named);
    };
    row("behavior decide", R"("targets": {"count": 10})", "behavior 'blame_behavior' (", 0);
    row("target kind in_view", R"("targets": {"kind": "blame_target", "count": 2000, "params": {"mode": 1}})",
        "target kind 'blame_target' (");
    row("contact handler on_contact, second in the list",
        R"("targets": {"count": 2000}, "contact_handlers": ["detect_targets", {"name": "blame_handler", "params": {"mode": 1}}])",
        "contact handler 'blame_handler' (");
    row("contact handler reset", R"("contact_handlers": [{"name": "blame_handler", "params": {"mode": 2}}])",
        "could not start: contact handler 'blame_handler' (");
    row("contact handler reset in a change",
        R"("contact_handlers": [{"name": "blame_handler", "params": {"mode": 3}}], "changes": [{"time": 1, "set": {"drones": 60}}])",
        "could not be applied: contact handler 'blame_handler' (");
    row("metric reset", R"("metrics": [{"name": "blame_metric", "params": {"mode": 2}}])", "metric 'blame_metric' (");
    row("metric observe", R"("metrics": [{"name": "blame_metric", "params": {"mode": 3}}])", "metric 'blame_metric' (");
    row("metric finish", R"("metrics": [{"name": "blame_metric", "params": {"mode": 4}}])", "metric 'blame_metric' (");
  }
  void every_failure_names_its_plugin() {
    QFETCH(QByteArray, test);
    QFETCH(QString, named);
    QTemporaryDir dir;
    write(dir.filePath("t.json"), test);
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--plugin-dir", q(test_plugins_dir() / "blame")}, dir.path());
    QVERIFY2(r.exit_code == 1 && !r.crashed, describe(r));
    QVERIFY2(non_empty_lines(r.err).size() == 1, describe(r));
    QVERIFY2(r.err.startsWith("salsa: test 'b' (t.json): "), describe(r));
    QVERIFY2(r.err.contains(named + q(test_plugins_dir() / "blame" / "libtest_blame.so") + ")"), describe(r));
    QVERIFY2(named.startsWith("behavior") || !r.err.contains("behavior 'blame_behavior'"), describe(r));
    QVERIFY2(!r.err.contains("detect_targets"), describe(r));
    QVERIFY2(r.err.contains(named.startsWith("behavior") ? "failed at t = 0 s: drone 0 threw" : "first line second line third line"),
             describe(r));
  }

  // decide and in_view run in parallel: the failure told is the lowest drone id's, whatever the
  // thread count and whichever thread threw first (2000 drones: many chunks of 64, run in any order).
  void parallel_failure_is_the_lowest_drone_id() {
    QTemporaryDir dir;
    write(dir.filePath("t.json"),
          R"({"name": "b", "behavior": {"name": "blame_behavior", "params": {"throw_from": 150}}, "drones": 2000, "time": 1})");
    for (const char* threads : {"1", "2", "2", "2"}) {  // more than the cores makes TBB warn on stderr
      const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--threads", threads, "--plugin-dir",
                                     q(test_plugins_dir() / "blame")},
                                    dir.path());
      QVERIFY2(r.exit_code == 1 && non_empty_lines(r.err).size() == 1, describe(r));
      QVERIFY2(r.err.contains("behavior 'blame_behavior' (") && r.err.contains("failed at t = 0 s: drone 150 threw"), describe(r));
    }
  }

  void isolate_fails_only_the_crashing_test_data() {
    QTest::addColumn<int>("mode");
    QTest::addColumn<QString>("what");
    QTest::newRow("segfault") << 1 << "died of SIGSEGV";
    QTest::newRow("std::exit") << 2 << "ended by a call to exit()";
    QTest::newRow("throw") << 3 << "failed at t = 0.5 s: crash plugin threw as asked";
    QTest::newRow("abort") << 4 << "died of SIGABRT";
  }
  void isolate_fails_only_the_crashing_test() {
    QFETCH(int, mode);
    QFETCH(QString, what);
    QTemporaryDir dir;
    const QByteArray before = R"({"name": "before", "behavior": "flocking", "drones": 4, "time": 1, "seed": 1})";
    const QByteArray after = R"({"name": "after", "behavior": "flocking", "drones": 4, "time": 1, "seed": 2})";
    write(dir.filePath("plain.json"), "[" + before + "," + after + "]");
    const QByteArray boom =
        QStringLiteral(R"({"name": "boom", "behavior": {"name": "test_crash", "params": {"mode": %1}}, "drones": 4, "time": 2})").arg(mode).toUtf8();
    write(dir.filePath("q.json"), "[" + before + "," + boom + "," + after + "]");
    const CliResult r = run_salsa({"run", "q.json", "--out", "out", "--isolate", "--plugin-dir", crash_plugins()}, dir.path());
    QVERIFY2(r.exit_code == 1 && !r.crashed && non_empty_lines(r.err).size() == 1, describe(r));
    QVERIFY2(r.err.contains("test 'boom' (q.json: [1])") && r.err.contains(what) && r.err.contains("libtest_crash.so"), describe(r));
    for (const char* name : {"before", "after"}) QVERIFY(QFileInfo::exists(dir.filePath(QString("out/") + name + "/config.json")));
    QVERIFY(!QFileInfo::exists(dir.filePath("out/boom")));
    // The isolated results are those of an ordinary run.
    const CliResult plain = run_salsa({"run", "plain.json", "--out", "plain"}, dir.path());
    QVERIFY2(plain.exit_code == 0, describe(plain));
    for (const char* name : {"before", "after"})
      QCOMPARE(results_snapshot(dir.filePath(QString("plain/") + name)), results_snapshot(dir.filePath(QString("out/") + name)));
  }

  // ---- Interruptions: stop cleanly, resume to byte-identical results.

  void interrupted_run_resumes_identically_data() {
    // When to send it, as a fraction of the uninterrupted run's time: the three tests take about a
    // third each, and drones.csv is written all the time (mid-write).
    QTest::addColumn<int>("sig");
    QTest::addColumn<double>("at");
    QTest::addColumn<bool>("isolate");
    QTest::newRow("SIGINT in the first test") << int(SIGINT) << 0.1 << false;
    QTest::newRow("SIGTERM in the second test") << int(SIGTERM) << 0.5 << false;
    QTest::newRow("SIGINT in the last test") << int(SIGINT) << 0.8 << false;
    QTest::newRow("SIGKILL at once") << int(SIGKILL) << 0.0 << false;
    QTest::newRow("SIGKILL in the first test") << int(SIGKILL) << 0.2 << false;
    QTest::newRow("SIGKILL in the second test") << int(SIGKILL) << 0.45 << false;
    QTest::newRow("SIGKILL in the last test") << int(SIGKILL) << 0.75 << false;
    QTest::newRow("SIGKILL near the end") << int(SIGKILL) << 0.9 << false;
    QTest::newRow("--isolate, SIGINT") << int(SIGINT) << 0.4 << true;
    QTest::newRow("--isolate, SIGTERM") << int(SIGTERM) << 0.6 << true;
  }
  void interrupted_run_resumes_identically() {
    QFETCH(int, sig);
    QFETCH(double, at);
    QFETCH(bool, isolate);
    QTemporaryDir dir;
    write(dir.filePath("queue.json"), queue);
    {
      QStringList args{"run", "queue.json", "--out", "out", "--threads", "1", "-q"};
      if (isolate) args << "--isolate";
      Background run(args, dir.path());
      QVERIFY(wait_for(dir.filePath("out/.a.partial/summary.csv")));
      QThread::msleep(static_cast<unsigned long>(at * static_cast<double>(reference_ms_)));
      run.signal(sig);
      const CliResult r = run.finish();
      if (r.crashed) {
        QCOMPARE(sig, int(SIGKILL));
      } else if (r.exit_code != 0) {  // 0: it had finished already (a slow start)
        QVERIFY2(r.exit_code == 128 + sig && non_empty_lines(r.err).size() == 1, describe(r));
        QVERIFY2(r.err.contains(sig == SIGINT ? "SIGINT" : "SIGTERM") && r.err.contains("--resume"), describe(r));
        // Where it stopped: a test's .partial folder, before the next test, or (the watchdog, when the
        // stop outlasts its grace between an --isolate child's end and the next) the bare stop.
        QVERIFY2(r.err.contains(".partial") || r.err.contains("stopped before") || r.err.contains("stopped by"), describe(r));
      }
    }
    // What is on disk is whole rows, in .partial folders or finished ones (a killed run's .partial
    // files but for their last line).
    check_whole_rows(dir.filePath("out"), sig == SIGKILL);
    if (sig == SIGKILL) {  // that cut, made sure of: --resume still gives the uninterrupted files
      for (const QString& partial : QDir(dir.filePath("out")).entryList({".*.partial"}, QDir::Dirs | QDir::Hidden)) {
        QFile csv(dir.filePath("out/" + partial + "/drones.csv"));
        if (csv.exists()) QVERIFY(csv.open(QIODevice::Append) && csv.write("12.3400,7,0.") == 12);
      }
    }
    const CliResult r = run_salsa({"run", "queue.json", "--out", "out", "--threads", "1", "--resume", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    QCOMPARE(results_snapshot(dir.filePath("out")), results_snapshot(reference()));
  }

  void full_disk_is_named_and_resumes_identically() {
    if (::geteuid() != 0) QSKIP("needs root to mount a small tmpfs");
    QTemporaryDir dir;
    const QString disk = dir.filePath("disk");
    QVERIFY(QDir().mkpath(disk));
    if (::mount("tmpfs", disk.toLocal8Bit().constData(), "tmpfs", 0, "size=200k") != 0) QSKIP("cannot mount a tmpfs here");
    auto unmount = qScopeGuard([&] { ::umount2(disk.toLocal8Bit().constData(), MNT_DETACH); });
    // "a" fits; "b" writes about 900 KB of drones.csv.
    const QByteArray small_queue = R"([
      {"name": "a", "behavior": "flocking", "drones": 5, "time": 2},
      {"name": "b", "behavior": "flocking", "drones": 100, "time": 10, "log_interval": 0.05}])";
    write(dir.filePath("q.json"), small_queue);
    CliResult r = run_salsa({"run", "q.json", "--out", disk + "/out", "--threads", "1", "--no-plots", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 1 && !r.crashed && non_empty_lines(r.err).size() == 1, describe(r));
    QVERIFY2(r.err.startsWith("salsa: test 'b' (q.json: [1]): " + disk + "/out/.b.partial/") && r.err.contains(".csv: write failed (disk full)"),
             describe(r));
    QVERIFY(QFileInfo::exists(disk + "/out/a/config.json"));
    QVERIFY(!QFileInfo::exists(disk + "/out/b"));
    // Space freed: --resume finishes, identical to a run on a roomy disk.
    QVERIFY(::mount("tmpfs", disk.toLocal8Bit().constData(), "tmpfs", MS_REMOUNT, "size=20m") == 0);
    r = run_salsa({"run", "q.json", "--out", disk + "/out", "--threads", "1", "--resume", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    r = run_salsa({"run", "q.json", "--out", "roomy", "--threads", "1", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(results_snapshot(disk + "/out"), results_snapshot(dir.filePath("roomy")));
  }
};

QTEST_GUILESS_MAIN(TestReliability)
#include "test_reliability.moc"
