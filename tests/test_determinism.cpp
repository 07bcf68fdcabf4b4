// Same test and seed give byte-identical output files, whatever the number of decide threads; a
// different seed gives different data. Over every built-in behavior, on a small forest with targets.
#include <QtTest>

#include "common.hpp"
#include "salsa/core/files/map_file.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa_test;

namespace {

const QStringList output_files{"config.json", "map.json", "summary.csv", "drones.csv", "targets.csv"};

QString test_json(const QString& behavior, int seed, int drones = 40) {
  return QString(R"({"name": "determinism", "behavior": "%1", "drones": %3,
                     "map": {"name": "forest", "params": {"size": 300}},
                     "targets": {"kind": "tree", "count": 60}, "time": 15, "log_interval": 0.5, "seed": %2})")
      .arg(behavior)
      .arg(seed)
      .arg(drones);
}

}  // namespace

class TestDeterminism : public QObject {
  Q_OBJECT

  std::unique_ptr<salsa::PluginHost> host_;

  /// Runs the test into a fresh folder under `root`; returns the test's output folder.
  QString run(const QString& behavior, int seed, int threads, const QString& root, int drones = 40) {
    const salsa::TestSpec test = salsa::parse_test(test_json(behavior, seed, drones).toStdString(), "determinism", *host_);
    salsa::RunOptions options;
    options.out = root.toStdString();
    options.threads = threads;
    const salsa::RunResult result = salsa::run_test(test, *host_, options);
    return q(result.folder);
  }

  void compare_outputs(const QString& a, const QString& b) {
    for (const QString& file : output_files) {
      const QByteArray x = read_file(a + "/" + file), y = read_file(b + "/" + file);
      QVERIFY2(!x.isEmpty(), qPrintable(a + "/" + file + " is missing or empty"));
      QVERIFY2(x == y, qPrintable(file + " differs between " + a + " and " + b));
    }
  }

 private Q_SLOTS:
  void initTestCase() {
    host_ = builtin_host();
    QVERIFY(host_->failures().empty());
    for (const char* name : {"flocking", "pheromone_avoidance", "dynamic_space_partitioning", "dynamic_space_partitioning_paper",
                             "random_walk"})
      QVERIFY2(!host_->behavior(name).factory.name.empty(), name);
  }

  // Every behavior the build ships, not just the five named above.
  void same_seed_same_bytes_data() {
    QTest::addColumn<QString>("behavior");
    for (const auto& e : host_->behaviors()) QTest::newRow(e.factory.name.c_str()) << q(e.factory.name);
  }
  void same_seed_same_bytes() {
    QFETCH(QString, behavior);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString first = run(behavior, 7, 2, dir.filePath("first"));
    const QString second = run(behavior, 7, 2, dir.filePath("second"));
    compare_outputs(first, second);
    // The data is not trivial: drones moved, and the run logged every 0.5 s for 15 s.
    const QByteArray drones = read_file(first + "/drones.csv");
    QCOMPARE(drones.count('\n'), 1 + 31 * 40);
    QVERIFY(read_file(first + "/summary.csv").count('\n') == 1 + 31);
  }

  void thread_count_does_not_change_the_bytes_data() { same_seed_same_bytes_data(); }
  void thread_count_does_not_change_the_bytes() {
    QFETCH(QString, behavior);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    // Enough drones that decide is really split between threads (it works in chunks of 64 drones).
    const QString serial = run(behavior, 9, 1, dir.filePath("serial"), 130);
    const QString parallel = run(behavior, 9, 2, dir.filePath("parallel"), 130);
    compare_outputs(serial, parallel);
  }

  void other_seed_other_data_data() { same_seed_same_bytes_data(); }
  void other_seed_other_data() {
    QFETCH(QString, behavior);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString a = run(behavior, 7, 2, dir.filePath("a"));
    const QString b = run(behavior, 8, 2, dir.filePath("b"));
    QVERIFY(read_file(a + "/drones.csv") != read_file(b + "/drones.csv"));
    QVERIFY(read_file(a + "/targets.csv") != read_file(b + "/targets.csv"));
    // config.json records the seed: enough to rerun it exactly.
    QVERIFY(read_file(a + "/config.json").contains("\"seed\": 7"));
    QVERIFY(read_file(b + "/config.json").contains("\"seed\": 8"));
  }

  // What docs/output-format.md promises: two identical runs of a queue differ only in the wall times
  // (timing.json per test, OUT/timing.csv) and in queue.json's record of the command line.
  void identical_queue_runs_write_identical_files() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QVERIFY(write_file(dir.filePath("q.json"), R"({"sweep": {"test": {"drones": 4, "time": 2, "targets": {"count": 5},
      "map": {"name": "forest", "params": {"size": 200}}}, "behaviors": ["flocking", "random_walk"]}, "repeats": 2})"));
    for (const char* out : {"a", "b"}) {
      const CliResult r = run_salsa({"run", "q.json", "--out", out, "-q", "--no-plots"}, dir.path());
      QVERIFY2(r.exit_code == 0, describe(r));
    }
    QDirIterator files(dir.filePath("a"), QDir::Files | QDir::Hidden, QDirIterator::Subdirectories);
    int compared = 0;
    while (files.hasNext()) {
      const QString a = files.next(), name = QFileInfo(a).fileName();
      if (name == "timing.json" || name == "timing.csv" || name == "queue.json") continue;
      const QString b = dir.filePath("b") + a.mid(dir.filePath("a").size());
      QVERIFY2(read_file(a) == read_file(b), qPrintable(a.mid(dir.path().size()) + " differs between identical runs"));
      ++compared;
    }
    QVERIFY2(compared > 4 * 5, "summary.csv, comparison.csv and the tests' files were compared");
  }

  void rerun_from_config_json_reproduces_the_run() {
    // config.json is "enough to rerun it exactly": run it as a test file and get the same bytes.
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString first = run("flocking", 21, 2, dir.filePath("first"));
    const QString config = dir.filePath("rerun.json");
    QVERIFY(QFile::copy(first + "/config.json", config));
    const auto tests = salsa::load_tests(config.toStdString(), *host_);
    QCOMPARE(tests.size(), std::size_t(1));
    salsa::RunOptions options;
    options.out = dir.filePath("second").toStdString();
    options.threads = 1;
    const salsa::RunResult r = salsa::run_test(tests[0], *host_, options);
    compare_outputs(first, q(r.folder));
  }

  // map.json is the map in the map file format: salsa validate takes it, the json map plugin reads it
  // back to the same MapData, writing that again gives the same bytes, and a test run on it (same
  // seed) gives the same data as the test run on the generated map. Also with hollow outlines and
  // lines (the warehouse map file).
  void map_json_is_the_same_map_data() {
    QTest::addColumn<QString>("map");
    QTest::newRow("generated forest") << R"({"name": "forest", "params": {"size": 300}})";
    QTest::newRow("map file") << "\"" + q(source_dir() / "examples/maps/warehouse.json") + "\"";
  }
  void map_json_is_the_same_map() {
    QFETCH(QString, map);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    auto spec = [&](const QString& m) {
      return salsa::parse_test(QString(R"({"name": "m", "behavior": "random_walk", "drones": 12, "map": %1,
          "targets": {"kind": "tree", "count": 40}, "time": 4, "log_interval": 0.5, "seed": 11})").arg(m).toStdString(), "m", *host_);
    };
    salsa::RunOptions options;
    options.out = dir.filePath("first").toStdString();
    options.threads = 1;
    const QString first = q(salsa::run_test(spec(map), *host_, options).folder);
    const QString file = first + "/map.json";
    const CliResult v = run_salsa({"validate", file});
    QVERIFY2(v.exit_code == 0 && v.out.contains(": ok (map)"), describe(v));

    const salsa::MapData original = salsa::make_setup(spec(map), *host_, 1).map;
    const salsa::MapData read = salsa::load_map_file(file.toStdString(), *host_);
    QVERIFY(read.bounds.min == original.bounds.min && read.bounds.max == original.bounds.max);
    QVERIFY(read.spawn == original.spawn);
    QVERIFY(read.obstacles == original.obstacles);
    QVERIFY(read.hollow == original.hollow);
    QVERIFY(read.lines == original.lines);
    QVERIFY(!read.obstacles.empty());
    QCOMPARE(QByteArray::fromStdString(salsa::map_json(read, read.spawn)), read_file(file));

    options.out = dir.filePath("second").toStdString();
    const QString second = q(salsa::run_test(spec("\"" + file + "\""), *host_, options).folder);
    for (const char* f : {"map.json", "targets.csv", "drones.csv", "summary.csv"})
      QVERIFY2(read_file(first + "/" + f) == read_file(second + "/" + f), f);
  }
};

QTEST_GUILESS_MAIN(TestDeterminism)
#include "test_determinism.moc"
