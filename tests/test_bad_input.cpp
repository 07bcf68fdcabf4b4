// Bad input gets one line (docs/reliability.md): the salsa CLI exits non-zero and prints exactly one line on
// stderr naming the file, the field and what is allowed, and writes nothing. Also: output folders
// that already hold results are never touched unless asked, and bad plugin files do not stop a run.
#include <QtTest>

#include "common.hpp"

using namespace salsa_test;

namespace {

const QByteArray ok_test = R"({"behavior": "flocking", "drones": 5, "time": 2})";

// A 100 m square with one square obstacle from min [40, 40], max [60, 60]; `spawn` is JSON or empty.
QByteArray map_with_obstacle(const QByteArray& spawn) {
  return R"({"bounds": {"min": [0, 0], "max": [100, 100]},)" + (spawn.isEmpty() ? QByteArray() : "\"spawn\": " + spawn + ",") +
         R"("obstacles": [[[40, 40], [60, 40], [60, 60], [40, 60]]]})";
}

const QByteArray test_using_map = R"({"behavior": "flocking", "drones": 5, "map": "map.json", "time": 2})";

}  // namespace

class TestBadInput : public QObject {
  Q_OBJECT

  /// Writes a queue of two short tests ("first", "second") to `test` and runs it into `out`.
  static CliResult run_two_tests(const QString& test, const QString& out) {
    if (!write_file(test, R"([{"name": "first", "behavior": "flocking", "drones": 5, "time": 2},
                              {"name": "second", "behavior": "random_walk", "drones": 5, "time": 2}])"))
      return {};
    return run_salsa({"run", test, "--out", out});
  }

 private Q_SLOTS:
  void one_line_error_data() {
    QTest::addColumn<QString>("command");     // run or validate
    QTest::addColumn<QString>("file");        // the file given on the command line (in a fresh folder)
    QTest::addColumn<QByteArray>("test");     // test.json's contents ("": none)
    QTest::addColumn<QByteArray>("map");      // map.json's contents ("": none)
    QTest::addColumn<QStringList>("options");
    QTest::addColumn<QStringList>("expected");  // substrings of the one line

    auto both = [](const char* name, const QByteArray& test, const QStringList& expected) {
      for (const char* command : {"run", "validate"})
        QTest::newRow(qPrintable(QString("%1 (%2)").arg(name, command)))
            << command << "test.json" << test << QByteArray() << QStringList() << expected;
    };
    both("malformed JSON", "{\"behavior\": \"flocking\",\n  \"drones\": 10,,\n}", {"test.json", "invalid JSON", "line 2"});
    both("not an object", "42", {"test.json", "must be an object"});
    both("unknown behavior", R"({"behavior": "flockin"})",
         {"test.json", "behavior", "unknown behavior 'flockin'", "known:", "flocking", "random_walk"});
    both("missing behavior", R"({"drones": 3})", {"test.json", "behavior", "missing"});
    both("unknown map", R"({"behavior": "flocking", "map": "nowhere"})",
         {"test.json", "map", "unknown map 'nowhere'", "known:", "forest"});
    both("unknown target kind", R"({"behavior": "flocking", "targets": {"kind": "rock", "count": 3}})",
         {"test.json", "targets.kind", "'rock'", "known:", "tree"});
    both("unknown drone configuration", R"({"behavior": "flocking", "drone": "huge"})",
         {"test.json", "drone", "'huge'", "known: small, medium, large"});
    both("unknown contact handler", R"({"behavior": "flocking", "contact_handlers": ["explode"]})",
         {"test.json", "contact_handlers[0]", "'explode'", "known:", "detect_targets"});
    // A contact handler's parameters (the test suite's test_dwell declares dwell in [0, 60] s).
    auto with_handler = [](const char* name, const QByteArray& test, const QStringList& expected) {
      for (const char* command : {"run", "validate"})
        QTest::newRow(qPrintable(QString("%1 (%2)").arg(name, command)))
            << command << "test.json" << test << QByteArray() << QStringList{"--plugin-dir", q(test_plugins_dir() / "contact")}
            << expected;
    };
    with_handler("contact handler parameter out of range",
                 R"({"behavior": "flocking", "contact_handlers": [{"name": "test_dwell", "params": {"dwell": -1}}]})",
                 {"test.json: contact_handlers[0].params.dwell: -1 is out of range (allowed: [0, 60] s)"});
    with_handler("contact handler parameter not a number",
                 R"({"behavior": "flocking", "contact_handlers": [{"name": "test_dwell", "params": {"dwell": "long"}}]})",
                 {"test.json: contact_handlers[0].params.dwell: \"long\" is not a number (allowed: [0, 60] s)"});
    with_handler("unknown contact handler parameter",
                 R"({"behavior": "flocking", "contact_handlers": ["detect_targets", {"name": "test_dwell", "params": {"dwel": 1}}]})",
                 {"test.json: contact_handlers[1].params.dwel: unknown parameter of contact handler 'test_dwell' (declared: dwell, drones_at_least)"});
    with_handler("parameter of a handler that declares none",
                 R"({"behavior": "flocking", "contact_handlers": [{"name": "detect_targets", "params": {"dwell": 1}}]})",
                 {"test.json: contact_handlers[0].params.dwell: unknown parameter of contact handler 'detect_targets' (declared: none)"});
    with_handler("contact handler with an unknown key",
                 R"({"behavior": "flocking", "contact_handlers": [{"name": "test_dwell", "param": {"dwell": 1}}]})",
                 {"test.json: contact_handlers[0].param: unknown key (allowed: name, params)"});
    with_handler("contact handlers not a list", R"({"behavior": "flocking", "contact_handlers": "detect_targets"})",
                 {"test.json: contact_handlers: \"detect_targets\" must be a list of handler names or {\"name\", \"params\"} objects"});
    both("parameter out of range", R"({"behavior": {"name": "flocking", "params": {"alignment_weight": 99}}})",
         {"test.json", "behavior.params.alignment_weight", "99", "[0, 10]"});
    both("parameter not a number", R"({"behavior": {"name": "flocking", "params": {"alignment_weight": "high"}}})",
         {"test.json", "behavior.params.alignment_weight", "[0, 10]"});
    both("unknown parameter", R"({"behavior": {"name": "flocking", "params": {"speed": 3}}})",
         {"test.json", "behavior.params.speed", "declared:", "alignment_weight"});
    both("map parameter out of range", R"({"behavior": "flocking", "map": {"name": "forest", "params": {"size": 5}}})",
         {"test.json", "map.params.size", "[50, 100000] m"});
    both("integer parameter with a fraction",
         R"({"behavior": {"name": "pheromone_avoidance", "params": {"directions": 4.5}}})",
         {"test.json", "behavior.params.directions", "whole number in [3, 64]"});
    for (const char* drones : {"-5", "0", "1e9", "2.5", "\"ten\""})
      both(qPrintable(QString("drones = %1").arg(drones)), QByteArray(R"({"behavior": "flocking", "drones": )") + drones + "}",
           {"test.json", "drones", "whole number in [1, 1000000]"});
    both("time = 0", R"({"behavior": "flocking", "time": 0})", {"test.json", "time", "0 is out of range", "allowed: ["});
    both("time < 0", R"({"behavior": "flocking", "time": -1})", {"test.json", "time", "allowed: ["});
    both("drone field out of range", R"({"behavior": "flocking", "drone": {"base": "small", "max_speed": -1}})",
         {"test.json", "drone.max_speed", "allowed: ["});
    both("unknown top-level key", R"({"behavior": "flocking", "colour": "red"})",
         {"test.json", "colour", "unknown key", "allowed: name, behavior"});
    both("unknown spawn mode", R"({"behavior": "flocking", "spawn": {"mode": "line"}})",
         {"test.json", "spawn.mode", "allowed: disc, uniform"});
    both("bad test in a queue", R"({"tests": [{"behavior": "flocking"}, {"behavior": "flocking", "drones": 0}]})",
         {"test.json", "tests[1]", "drones"});
    both("duplicate test names", R"([{"name": "a", "behavior": "flocking"}, {"name": "a", "behavior": "random_walk"}])",
         {"test.json", "[1]", "name", "\"a\" is already used by"});
    both("empty list", "[]", {"test.json", "no tests"});
    both("100,000 levels of nesting", "{\"behavior\": " + QByteArray(100000, '[') + QByteArray(100000, ']') + "}",
         {"test.json: line 1, column 77: nested deeper than 64 levels (allowed: at most 64)"});
    both("duplicate key", R"({"behavior": "flocking", "drones": 3, "drones": 4})", {"test.json: drones: duplicate key"});
    both("number overflowing a double", R"({"behavior": "flocking", "time": 1e400})",
         {"test.json: line 1, column 34: 1e400 does not fit a double", "allowed: finite numbers"});
    both("NaN", R"({"behavior": "flocking", "time": NaN})", {"test.json: line 1, column 34: JSON has no NaN or Infinity"});
    both("tiny value shown exactly", R"({"behavior": "flocking", "time": 1e-9})", {"time: 1e-09 is out of range"});

    // Map files: checked by `salsa validate map.json`, and through a test that uses them.
    auto map_case = [](const char* name, const QByteArray& map, const QStringList& expected_validate,
                       const QStringList& expected_run) {
      QTest::newRow(qPrintable(QString("%1 (validate map)").arg(name)))
          << "validate" << "map.json" << QByteArray() << map << QStringList() << expected_validate;
      QTest::newRow(qPrintable(QString("%1 (run a test using it)").arg(name)))
          << "run" << "test.json" << test_using_map << map << QStringList() << expected_run;
    };
    map_case("spawn inside an obstacle", map_with_obstacle("[50, 50]"), {"map.json", "spawn", "[50, 50]", "obstacles[0]"},
             {"map.json", "spawn", "[50, 50]", "obstacles[0]"});
    map_case("default spawn inside an obstacle", map_with_obstacle(""), {"map.json", "spawn", "[50, 50] is inside obstacles[0]"},
             {"map.json", "spawn", "[50, 50] is inside obstacles[0]"});
    map_case("spawn too close to an obstacle", map_with_obstacle("[39.5, 50]"),
             {"map.json", "spawn", "[39.5, 50]", "free space"}, {"test.json", "map.json", "spawn", "[39.5, 50]", "free space"});
    map_case("spawn outside the bounds", map_with_obstacle("[150, 10]"), {"map.json", "spawn", "[150, 10]", "outside"},
             {"map.json", "spawn", "[150, 10]", "outside"});
    map_case("polygon with 2 points", R"({"bounds": {"min": [0, 0], "max": [100, 100]}, "obstacles": [[[40, 40], [60, 40]]]})",
             {"map.json", "obstacles[0]", "at least 3 points"}, {"map.json", "obstacles[0]", "at least 3 points"});
    // The map creator's rules hold for a map file however it is used (one set of rules, map_check.hpp).
    map_case("polygon whose edges cross", R"({"bounds": {"min": [0, 0], "max": [100, 100]}, "spawn": [10, 10],
               "obstacles": [[[40, 40], [60, 60], [60, 40], [40, 60]]]})",
             {"map.json", "obstacles[0]", "edges 0 and 2 cross"}, {"test.json", "map.json", "obstacles[0]", "edges 0 and 2 cross"});
    map_case("missing bounds", R"({"spawn": [5, 5], "obstacles": [[[40, 40], [60, 40], [50, 50]]]})",
             {"map.json", "bounds", "missing"}, {"map.json", "bounds", "missing"});
    map_case("bounds.max below bounds.min", R"({"bounds": {"min": [0, 0], "max": [-100, 100]}})",
             {"map.json", "bounds.max", "greater than bounds.min"}, {"map.json", "bounds.max", "greater than bounds.min"});
    map_case("point outside the bounds", R"({"bounds": {"min": [0, 0], "max": [100, 100]}, "lines": [[[10, 10], [200, 10]]]})",
             {"map.json", "lines[0][1]", "[200, 10]", "outside"}, {"map.json", "lines[0][1]", "outside"});
    map_case("unknown map key", R"({"bounds": {"min": [0, 0], "max": [100, 100]}, "walls": []})",
             {"map.json", "walls", "allowed: bounds, spawn, obstacles, hollow, lines"},
             {"map.json", "walls", "allowed: bounds, spawn, obstacles, hollow, lines"});
    map_case("malformed map JSON", "{\"bounds\": {\"min\": [0, 0],\n  \"max\": [100 100]}}", {"map.json", "invalid JSON", "line 2"},
             {"map.json", "invalid JSON", "line 2"});
    QTest::newRow("spawn.point inside an obstacle (run)")
        << "run" << "test.json"
        << QByteArray(R"({"behavior": "flocking", "map": "map.json", "spawn": {"point": [50, 50]}})")
        << map_with_obstacle("[10, 10]") << QStringList() << QStringList{"test.json", "spawn.point", "[50, 50]", "free space"};
    QTest::newRow("missing map file (run)")
        << "run" << "test.json" << test_using_map << QByteArray() << QStringList() << QStringList{"map.json", "cannot open"};

    // Command-line options and files.
    auto option = [](const char* name, const QStringList& options, const QStringList& expected) {
      QTest::newRow(name) << "run" << "test.json" << ok_test << QByteArray() << options << expected;
    };
    option("--threads -1", {"--threads", "-1"}, {"--threads", "-1", "allowed"});
    option("--time -3", {"--time", "-3"}, {"--time", "-3", "allowed"});
    option("--time 0", {"--time", "0"}, {"--time", "allowed"});
    option("--log-interval 0", {"--log-interval", "0"}, {"--log-interval", "allowed"});
    option("--threads two", {"--threads", "two"}, {"--threads", "two"});
    option("unknown option", {"--frobnicate"}, {"--frobnicate"});
    for (const char* command : {"run", "validate"})
      QTest::newRow(qPrintable(QString("nonexistent file (%1)").arg(command)))
          << command << "missing.json" << QByteArray() << QByteArray() << QStringList() << QStringList{"missing.json", "cannot open"};
  }

  void one_line_error() {
    QFETCH(QString, command);
    QFETCH(QString, file);
    QFETCH(QByteArray, test);
    QFETCH(QByteArray, map);
    QFETCH(QStringList, options);
    QFETCH(QStringList, expected);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    if (!test.isEmpty()) QVERIFY(write_file(dir.filePath("test.json"), test));
    if (!map.isEmpty()) QVERIFY(write_file(dir.filePath("map.json"), map));
    QStringList args{command, dir.filePath(file)};
    if (command == "run") args << "--out" << dir.filePath("out");
    args << options;
    const auto before = snapshot(dir.path());
    const CliResult r = run_salsa(args);
    QVERIFY2(!r.crashed, describe(r));
    QVERIFY2(r.exit_code != 0, describe(r));
    const QStringList lines = non_empty_lines(r.err);
    QVERIFY2(lines.size() == 1, describe(r));
    for (const QString& part : expected)
      QVERIFY2(lines[0].contains(part), qPrintable("'" + part + "' missing from the message\n" + describe(r)));
    QVERIFY2(r.out.trimmed().isEmpty(), describe(r));  // no progress lines: nothing ran
    QVERIFY2(!QFileInfo::exists(dir.filePath("out")), "nothing may be written on bad input");
    QVERIFY2(snapshot(dir.path()) == before, "the folder around the input changed");
  }

  // ---------------------------------------------------------------- existing output folders
  void existing_output_is_refused_and_left_alone() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString test = dir.filePath("queue.json"), out = dir.filePath("out");
    CliResult r = run_two_tests(test, out);
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto before = snapshot(out);
    // 2 tests × .salsa-test, config.json, manifest.json, map.json, summary.csv, drones.csv, targets.csv, outcome.csv;
    // the queue's summary.csv, comparison.csv and ranking.csv (plots left out)
    QCOMPARE(results_snapshot(out).size(), 19);

    r = run_salsa({"run", test, "--out", out});
    QVERIFY2(!r.crashed && r.exit_code != 0, describe(r));
    const QStringList lines = non_empty_lines(r.err);
    QVERIFY2(lines.size() == 1 && lines[0].contains(out + "/first") && lines[0].contains("already exists") &&
                 lines[0].contains("--resume") && lines[0].contains("--force"),
             describe(r));
    QVERIFY2(snapshot(out) == before, "a refused run must leave the existing files byte-identical");

    // Only the second test's folder exists: refused before the first test runs, nothing written.
    QVERIFY(QDir(out + "/first").removeRecursively());
    const auto second_only = snapshot(out);
    r = run_salsa({"run", test, "--out", out});
    QVERIFY2(r.exit_code != 0 && r.err.contains(out + "/second"), describe(r));
    QVERIFY2(snapshot(out) == second_only, "nothing may run when a later test's folder is taken");
    QVERIFY(!QFileInfo::exists(out + "/first"));
  }

  void resume_skips_finished_tests() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString test = dir.filePath("queue.json"), out = dir.filePath("out");
    CliResult r = run_two_tests(test, out);
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto all = results_snapshot(out);
    QVERIFY(QDir(out + "/second").removeRecursively());  // as if interrupted before the second test
    const auto first_only = snapshot(out + "/first");

    r = run_salsa({"run", test, "--out", out, "--resume"});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    QVERIFY2(r.out.contains("first: already complete, skipped"), describe(r));
    QVERIFY2(!r.out.contains("second: already complete"), describe(r));
    const auto after = snapshot(out + "/first");
    for (auto it = first_only.begin(); it != first_only.end(); ++it)
      QVERIFY2(after.value(it.key()) == it.value(), qPrintable(it.key() + " changed although it was skipped"));
    QVERIFY2(results_snapshot(out) == all, "the resumed test must write what the uninterrupted run wrote");

    // A folder without config.json is not a finished test: --resume refuses to guess, in one line
    // (and salsa did not write this one, so --force would not replace it either).
    QVERIFY(QDir(out + "/second").removeRecursively());
    QVERIFY(write_file(out + "/second/notes.txt", "mine\n"));
    r = run_salsa({"run", test, "--out", out, "--resume"});
    QVERIFY2(!r.crashed && r.exit_code != 0, describe(r));
    QVERIFY2(non_empty_lines(r.err).size() == 1 && r.err.contains(out + "/second") && r.err.contains("--resume cannot skip it") &&
                 r.err.contains("left alone"),
             describe(r));
    QCOMPARE(read_file(out + "/second/notes.txt"), QByteArray("mine\n"));
  }

  void force_replaces_finished_tests() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString test = dir.filePath("one.json");
    QVERIFY(write_file(test, R"({"name": "one", "behavior": "flocking", "drones": 5, "time": 2})"));
    const QString out = dir.filePath("out");
    CliResult r = run_salsa({"run", test, "--out", out});
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(write_file(out + "/one/stale.txt", "left over\n"));
    r = run_salsa({"run", test, "--out", out, "--force", "--time", "4"});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    QVERIFY2(!QFileInfo::exists(out + "/one/stale.txt"), "--force replaces the whole folder");
    QVERIFY(read_file(out + "/one/config.json").contains("\"time\": 4.0"));
    QCOMPARE(non_empty_lines(QString::fromUtf8(read_file(out + "/one/summary.csv"))).size(), 1 + 5);  // t = 0..4 s
    // No leftover .partial folder; the queue's own files beside the test.
    QCOMPARE(QDir(out).entryList(QDir::AllEntries | QDir::NoDotAndDotDot | QDir::Hidden), (QStringList{"comparison.csv", "one", "plots", "queue.json", "ranking.csv", "summary.csv", "timing.csv"}));
  }

  // ---------------------------------------------------------------- bad plugins
  void bad_plugins_warn_but_run_works() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString plugins = dir.filePath("plugins");
    QVERIFY(QDir().mkpath(plugins));
    QVERIFY(QFile::copy(q(test_plugins_dir() / "abi99/libtest_abi99.so"), plugins + "/libtest_abi99.so"));
    QVERIFY(QFile::copy(q(test_plugins_dir() / "notalib/notalib.so"), plugins + "/notalib.so"));
    QVERIFY(QFile::copy(q(test_plugins_dir() / "noentry/libtest_noentry.so"), plugins + "/libtest_noentry.so"));
    QVERIFY(write_file(dir.filePath("test.json"), ok_test));
    const CliResult r = run_salsa({"run", dir.filePath("test.json"), "--out", dir.filePath("out"), "--plugin-dir", plugins});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    const QStringList warnings = non_empty_lines(r.err);
    QCOMPARE(warnings.size(), 3);  // one line per refused file
    for (const QString& w : warnings) QVERIFY2(w.startsWith("salsa: warning: plugin " + plugins + "/"), describe(r));
    QVERIFY2(r.err.contains("libtest_abi99.so skipped: built for salsa ABI 99, this is 11"), describe(r));
    QVERIFY2(r.err.contains("notalib.so skipped: not a shared library"), describe(r));
    QVERIFY2(r.err.contains("libtest_noentry.so skipped: no entry point"), describe(r));
    QVERIFY2(QFileInfo(dir.filePath("out/test/config.json")).size() > 0, describe(r));
    // --quiet silences the warnings.
    const CliResult quiet =
        run_salsa({"run", dir.filePath("test.json"), "--out", dir.filePath("quiet"), "--plugin-dir", plugins, "--quiet"});
    QVERIFY2(quiet.exit_code == 0 && quiet.err.trimmed().isEmpty() && quiet.out.trimmed().isEmpty(), describe(quiet));
  }
};

QTEST_GUILESS_MAIN(TestBadInput)
#include "test_bad_input.moc"
