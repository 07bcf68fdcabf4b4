// Shared state over the radio: dynamic space partitioning's two versions with `sharing` 1 (each drone
// partitions from the points its radio heard), every built-in's shared-state declaration, and the
// warning of a queue that compares global knowledge with a radio.
#include <QTemporaryDir>
#include <QtTest>

#include <cmath>
#include <string>
#include <vector>

#include "common.hpp"
#include "salsa/behaviors/dynamic_space_partitioning.hpp"
#include "salsa/behaviors/dynamic_space_partitioning_paper.hpp"
#include "salsa/core/experiments/shared_state.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/fixture.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

constexpr const char* kPerfect = R"(, "comm": {"range": 100000, "line_of_sight": false})";

/// A behavior object with `sharing` set, its other parameters at their defaults.
template <class B>
std::shared_ptr<B> with_sharing(int sharing) {
  auto b = std::make_shared<B>();
  ParameterValues v;
  v.set("sharing", sharing);
  b->set_parameters(v);
  return b;
}

}  // namespace

class TestRadioSharing : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

  /// fraction_found at the end of the test, in percent.
  double found(const std::string& behavior, int seed, int sharing, const std::string& comm) {
    const std::string json = "{\"name\": \"p\", \"behavior\": {\"name\": \"" + behavior + "\", \"params\": {\"sharing\": " +
                             std::to_string(sharing) + "}}, \"drones\": 6, \"map\": {\"name\": \"empty\", \"params\": {\"size\": 600}}, " +
                             "\"targets\": {\"count\": 1000}, \"time\": 100, \"seed\": " + std::to_string(seed) + comm + "}";
    const TestSpec test = parse_test(json, "sharing.json", *host_);
    QTemporaryDir out;
    RunOptions options;
    options.out = out.path().toStdString();
    options.drones_csv = false;
    run_test(test, *host_, options);
    CsvReader outcome((out.path() + "/p/outcome.csv").toStdString());
    const std::size_t column = outcome.column("fraction_found");
    double last = -1;
    while (outcome.next()) last = outcome.number(column);
    return 100 * last;
  }

  /// Radio minus global over 8 worlds: within the paired 95 % interval of 0 (or under 1 point).
  void perfect_radio_matches_global(const std::string& behavior) {
    std::vector<double> d;
    for (int seed = 1; seed <= 8; ++seed) d.push_back(found(behavior, seed, 1, kPerfect) - found(behavior, seed, 0, ""));
    double mean = 0, ss = 0;
    for (double x : d) mean += x;
    mean /= static_cast<double>(d.size());
    for (double x : d) ss += (x - mean) * (x - mean);
    const double half = 2.365 * std::sqrt(ss / 7 / 8);  // t(0.975, 7 df) × sd / √n
    qInfo("%s: radio over a perfect radio − global: %+.2f ± %.2f points", behavior.c_str(), mean, half);
    QVERIFY2(std::abs(mean) <= std::max(half, 1.0), "a perfect radio should partition as the global points do");
  }

  /// `salsa validate` of a queue of these tests: its stderr.
  QString validate(const QString& tests) {
    QTemporaryDir dir;
    const QString file = dir.filePath("q.json");
    QFile f(file);
    f.open(QIODevice::WriteOnly);
    f.write(("{\"repeats\": 1, \"base\": {\"drones\": 3, \"time\": 2, \"targets\": {\"count\": 5}}, \"tests\": [" + tests + "]}").toUtf8());
    f.close();
    const CliResult r = run_salsa({"validate", file});
    if (r.exit_code != 0) qWarning("%s", describe(r).constData());
    return r.err;
  }

 private Q_SLOTS:
  void dsp_over_a_perfect_radio_finds_what_the_global_partition_finds() { perfect_radio_matches_global("dynamic_space_partitioning"); }
  void paper_dsp_over_a_perfect_radio_finds_what_the_global_points_find() {
    perfect_radio_matches_global("dynamic_space_partitioning_paper");
  }

  void without_a_radio_each_drone_partitions_alone() {
    const std::string base = R"("drones": 5, "map": {"name": "empty", "params": {"size": 400}}, "targets": {"count": 10}, "seed": 4)";
    for (const std::string& comm : {std::string(), std::string(R"(, "comm": {"range": 0.001})")}) {
      auto dsp = with_sharing<behaviors::DynamicSpacePartitioning>(1);
      testing::Simulation sim(dsp, "{" + base + comm + "}");
      sim.run(10);
      for (std::uint32_t i = 0; i < 5; ++i) {
        QCOMPARE(dsp->heard_points(i).known().size(), std::size_t{1});  // its own point alone
        QCOMPARE(dsp->heard_points(i).known()[0].first, i);
        // Nothing pushes it: the point stays where the drone started; its region is the whole map.
        QVERIFY(std::abs(dsp->heard_points(i).spacing() - 400) < 1e-9);
        QVERIFY2(QString::fromStdString(dsp->inspect(i)).startsWith("region: 400 cells"), dsp->inspect(i).c_str());
      }
      auto paper = with_sharing<behaviors::DynamicSpacePartitioningPaper>(1);
      testing::Simulation walk(paper, "{" + base + comm + "}");
      walk.run(10);
      for (std::uint32_t i = 0; i < 5; ++i) QCOMPARE(paper->heard_points(i).known().size(), std::size_t{1});
    }
  }

  void over_a_radio_each_drone_hears_every_point() {
    const std::string test = R"({"drones": 5, "map": {"name": "empty", "params": {"size": 400}}, "targets": {"count": 10}, "seed": 4)" +
                             std::string(kPerfect) + "}";
    auto dsp = with_sharing<behaviors::DynamicSpacePartitioning>(1);
    testing::Simulation sim(dsp, test);
    sim.run(20);
    std::size_t owned = 0;
    for (std::uint32_t i = 0; i < 5; ++i) {
      QCOMPARE(dsp->heard_points(i).known().size(), std::size_t{5});
      QVERIFY(std::abs(dsp->heard_points(i).spacing() - std::sqrt(400.0 * 400 / 5)) < 1e-9);
      owned += std::stoul(dsp->inspect(i).substr(std::string("region: ").size()));
    }
    // The drones' own partitions agree closely (their views lag a step or two): about one tiling.
    QVERIFY2(owned >= 390 && owned <= 410, std::to_string(owned).c_str());
    auto paper = with_sharing<behaviors::DynamicSpacePartitioningPaper>(1);
    testing::Simulation walk(paper, test);
    walk.run(20);
    for (std::uint32_t i = 0; i < 5; ++i) QCOMPARE(paper->heard_points(i).known().size(), std::size_t{5});
  }

  void every_built_in_declares_its_shared_state() {
    auto declared = [&](const std::string& name, std::optional<int> sharing) {
      PluginChoice choice{name, {}};
      for (const auto& p : host_->behavior(name).factory.parameters) choice.params.set(p.name, p.value);
      if (sharing) choice.params.set("sharing", *sharing);
      return std::string(to_string(shared_state_of(choice, *host_)));
    };
    for (const char* name : {"pheromone_avoidance", "dynamic_space_partitioning", "dynamic_space_partitioning_paper"}) {
      QCOMPARE(declared(name, std::nullopt), std::string("global"));  // the default: the paper's shared state
      QCOMPARE(declared(name, 0), std::string("global"));
      QCOMPARE(declared(name, 1), std::string("radio"));
    }
    QCOMPARE(declared("flocking", std::nullopt), std::string("none"));  // neighbours are sensed, not shared
    QCOMPARE(declared("random_walk", std::nullopt), std::string("none"));
  }

  void a_queue_of_global_knowledge_and_a_radio_is_warned_about() {
    const QString warning = "compares global knowledge with a radio";
    const QString radio_dsp = R"({"name": "r", "behavior": {"name": "dynamic_space_partitioning", "params": {"sharing": 1}}, "comm": {"range": 50}})";
    // Global DSP beside a radio test: warned, naming the global variant.
    QString err = validate(R"({"name": "g", "behavior": "dynamic_space_partitioning"}, )" + radio_dsp);
    QVERIFY2(err.contains(warning) && err.contains("dynamic_space_partitioning (defaults)") && err.contains("e.g. r"), qPrintable(err));
    // A global behavior in a test with a radio: warned too.
    err = validate(R"({"name": "g", "behavior": "pheromone_avoidance", "comm": {"range": 50}})");
    QVERIFY2(err.contains(warning), qPrintable(err));
    // Radio modes and behaviors without shared state over a radio: no warning.
    err = validate(radio_dsp + R"(, {"name": "f", "behavior": "flocking", "comm": {"range": 50}}, {"name": "w", "behavior": "random_walk"})");
    QVERIFY2(!err.contains(warning), qPrintable(err));
    // Global behaviors without any radio: a fair comparison of global knowledge, no warning.
    err = validate(R"({"name": "g", "behavior": "dynamic_space_partitioning"}, {"name": "p", "behavior": "pheromone_avoidance"})");
    QVERIFY2(!err.contains(warning), qPrintable(err));
  }

  void a_run_records_the_warning_beside_its_comparison() {
    QTemporaryDir dir;
    auto write = [&](const QString& name, const QString& tests) {
      QFile f(dir.filePath(name));
      f.open(QIODevice::WriteOnly);
      f.write(("{\"repeats\": 2, \"base\": {\"drones\": 3, \"time\": 2, \"targets\": {\"count\": 5}}, \"tests\": [" + tests + "]}").toUtf8());
    };
    write("mixed.json", R"({"name": "g", "behavior": "dynamic_space_partitioning", "comm": {"range": 50}}, {"name": "w", "behavior": "random_walk", "comm": {"range": 50}})");
    write("fair.json", R"({"name": "g", "behavior": "dynamic_space_partitioning"}, {"name": "w", "behavior": "random_walk"})");
    CliResult r = run_salsa({"run", dir.filePath("mixed.json"), "--out", dir.filePath("mixed"), "--no-plots"});
    QVERIFY2(r.exit_code == 0 && r.err.contains("salsa: warning: the queue compares global knowledge with a radio"), describe(r));
    const QByteArray notes = read_file(dir.filePath("mixed") + "/comparison_notes.txt");
    QVERIFY2(notes.startsWith("the queue compares global knowledge with a radio") && notes.endsWith("\n"), notes.constData());
    QVERIFY(read_file(dir.filePath("mixed") + "/queue.json").contains("\"warnings\""));
    r = run_salsa({"run", dir.filePath("fair.json"), "--out", dir.filePath("fair"), "--no-plots"});
    QVERIFY2(r.exit_code == 0 && !r.err.contains("warning"), describe(r));
    QVERIFY(!QFileInfo::exists(dir.filePath("fair") + "/comparison_notes.txt"));
    QVERIFY(!read_file(dir.filePath("fair") + "/queue.json").contains("\"warnings\""));
  }
};

QTEST_GUILESS_MAIN(TestRadioSharing)
#include "test_radio_sharing.moc"
