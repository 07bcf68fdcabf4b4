// The plugin authors' stepping fixture (salsa/fixture.hpp): a real simulation a test steps, with
// prepare(), shared state, drones' own random streams, maps, targets and metrics.
#include <salsa/behaviors/dynamic_space_partitioning_paper.hpp>
#include <salsa/fixture.hpp>
#include <salsa/sdk.hpp>

#include <QtTest>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "common.hpp"

using salsa::Vec2;

namespace {

/// Shared state: prepare() finds the swarm's centre once a step; every drone flies straight away from it.
class Scatter final : public salsa::Behavior {
  salsa::Param weight{this, "weight", 1.0, 0.0, 10.0, "", "how hard to flee the centre"};

 public:
  int prepared = 0;
  Vec2 centre;
  void prepare(const salsa::WorldView& world) override {
    ++prepared;
    centre = {};
    for (Vec2 p : world.drone_positions()) centre += p;
    centre = centre / static_cast<double>(world.drone_positions().size());
  }
  Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    return weight * salsa::steer_along(me, me.position - centre);
  }
};

double mean_distance_to_centre(std::span<const Vec2> positions) {
  Vec2 c;
  for (Vec2 p : positions) c += p;
  c = c / static_cast<double>(positions.size());
  double sum = 0;
  for (Vec2 p : positions) sum += salsa::distance(p, c);
  return sum / static_cast<double>(positions.size());
}

const std::string kTestPlugin = SALSA_TEST_PLUGINS_DIR "/metric/libtest_metric.so";

}  // namespace

class TestFixture : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  // A behavior object with shared state: prepare runs once a step before the decisions, and its effect
  // shows in the drones' positions.
  void shared_state_behavior() {
    auto scatter = std::make_shared<Scatter>();
    salsa::testing::Simulation sim(scatter, R"({"drones": 12, "map": {"name": "empty", "params": {"size": 2000}}, "seed": 5})");
    QCOMPARE(scatter->parameters().get("weight"), 1.0);  // its Param defaults
    const double before = mean_distance_to_centre(sim.positions());
    sim.run(10);
    QCOMPARE(scatter->prepared, 600);
    QVERIFY(std::abs(sim.time() - 10) < 1e-9);
    const double after = mean_distance_to_centre(sim.positions());
    // Fleeing at up to 10 m/s (the small drone) for 10 s, accelerating from rest at 0.3 m/s a step.
    QVERIFY2(after > before + 50 && after < before + 100, qPrintable(QString("%1 -> %2").arg(before).arg(after)));
    // The fixture's world is the running simulation's.
    QCOMPARE(sim.world().drone_positions().size(), std::size_t(12));
    QCOMPARE(sim.world().bounds().max, Vec2(2000, 2000));
  }

  // By name: salsa's built-ins load, targets are found, metrics read, and the same seed repeats.
  void builtins_targets_and_metrics() {
    const std::string test = R"({"behavior": "random_walk", "drones": 10, "targets": {"kind": "tree", "count": 300},
                                 "map": {"name": "empty", "params": {"size": 400}}, "seed": 9})";
    salsa::testing::Simulation sim(test);
    QCOMPARE(sim.targets(), std::size_t(300));
    QCOMPARE(sim.target_positions().size(), std::size_t(300));
    QCOMPARE(sim.metric("coverage"), sim.metric("coverage"));
    const double early = sim.metric("coverage");
    sim.run(30);
    QVERIFY(sim.targets_found() > 10);
    QVERIFY(sim.metric("coverage") > early);
    QVERIFY(sim.metric_columns().size() >= 1);
    QVERIFY_THROWS_EXCEPTION(std::out_of_range, sim.metric("no_such_column"));

    salsa::testing::Simulation again(test);
    again.run(30);
    QCOMPARE(again.targets_found(), sim.targets_found());
    for (std::size_t i = 0; i < 10; ++i) QCOMPARE(again.positions()[i], sim.positions()[i]);
    salsa::testing::Simulation other(R"({"behavior": "random_walk", "drones": 10, "seed": 10,
                                         "map": {"name": "empty", "params": {"size": 400}}})");
    other.run(30);
    QVERIFY(other.positions()[0] != sim.positions()[0]);
  }

  // The author's plugin file: loaded first, its behavior and metric run.
  void plugin_file() {
    salsa::testing::Simulation sim(R"({"behavior": "test_straight", "drones": 3, "metrics": ["test_metric"],
                                       "map": {"name": "empty", "params": {"size": 1000}}})",
                                   {kTestPlugin});
    const Vec2 start = sim.positions()[0];
    sim.run(2);
    QVERIFY(sim.positions()[0].x > start.x + 5);
    QCOMPARE(sim.metric("test_steps"), 120.0);
    QVERIFY(sim.behavior().parameters().items().empty());
  }

  // The paper's dynamic space partitioning, against its definition: the points spread over the map,
  // and each drone random-walks within the disc of radius disc_fraction × √(area / drones) around its
  // point. While the points spread (at point_speed, 8 m/s, for the first minute) they may outrun their
  // drones; once they have slowed down (the fastest under 3 m/s, measured at 87 s), every drone that
  // is in its disc stays there, up to one step's flight (it decided before it flew), for the rest of
  // 5 minutes (measured: never past it). It walks: it does not hover at its point.
  void paper_dsp_walks_within_its_disc() {
    auto dsp = std::make_shared<salsa::behaviors::DynamicSpacePartitioningPaper>();
    const std::size_t n = 20;
    salsa::testing::Simulation sim(dsp, R"({"drones": 20, "map": {"name": "empty", "params": {"size": 1000}}, "seed": 4})");
    const double dt = sim.world().dt(), slack = 10 * dt;  // the small drone's max speed × dt
    std::vector<char> inside(n, 0);
    std::vector<double> sum(n, 0);
    std::vector<int> samples(n, 0);
    std::vector<Vec2> before(n);
    double worst = 0, radius = 0, settled = -1;
    for (int step = 1; step <= 300 * 60; ++step) {
      for (std::uint32_t i = 0; i < n && step > 1; ++i) before[i] = dsp->points()[i];
      sim.step();
      radius = dsp->disc_radius();
      double fastest = 0;
      for (std::uint32_t i = 0; i < n; ++i) fastest = std::max(fastest, salsa::distance(before[i], dsp->points()[i]) / dt);
      if (settled < 0 && step > 1 && fastest < 3) settled = sim.time();
      if (settled < 0) continue;
      for (std::uint32_t i = 0; i < n; ++i) {
        const double d = salsa::distance(sim.positions()[i], dsp->points()[i]);
        if (d <= radius) inside[i] = 1;
        if (!inside[i]) continue;
        worst = std::max(worst, d - radius);
        sum[i] += d, ++samples[i];
      }
    }
    double nearest = 1e9;
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t j = 0; j < i; ++j) nearest = std::min(nearest, salsa::distance(dsp->points()[i], dsp->points()[j]));
    qInfo("points settled at %.1f s; disc radius %.1f m; closest two points %.1f m apart; worst excursion past a disc %.3f m",
          settled, radius, nearest, worst);
    QCOMPARE(radius, 0.3 * std::sqrt(1000.0 * 1000.0 / n));
    QVERIFY2(settled >= 0 && settled < 120, "the points did not slow down within two minutes");
    QVERIFY2(nearest > 2 * radius, "discs overlap: the points did not spread");
    QVERIFY2(std::all_of(inside.begin(), inside.end(), [](char c) { return c; }), "a drone never reached its disc");
    QVERIFY2(worst <= slack, qPrintable(QString("a drone left its disc by %1 m").arg(worst)));
    for (std::uint32_t i = 0; i < n; ++i)  // a walk over the disc: mean distance from the point 2/3 r if uniform
      QVERIFY2(sum[i] / samples[i] > 0.3 * radius, qPrintable(QString("drone %1 stays near its point").arg(i)));
  }

  // Bad input fails the author's test with salsa's own one-line messages.
  void bad_input() {
    try {
      salsa::testing::Simulation sim(R"({"behavior": "random_walk", "drones": 0})");
      QFAIL("no error");
    } catch (const std::runtime_error& e) {
      QVERIFY2(QString(e.what()).contains("drones"), e.what());
    }
    try {
      salsa::testing::Simulation sim(R"({"behavior": "random_walk"})", {SALSA_TEST_PLUGINS_DIR "/notalib/notalib.so"});
      QFAIL("no error");
    } catch (const std::runtime_error& e) {
      QVERIFY2(QString(e.what()).startsWith(SALSA_TEST_PLUGINS_DIR "/notalib/notalib.so: "), e.what());
    }
    try {
      salsa::testing::Simulation sim(R"({"behavior": "test_straight"})");  // not loaded: only the built-ins are
      QFAIL("no error");
    } catch (const std::runtime_error& e) {
      QVERIFY2(QString(e.what()).contains("test_straight"), e.what());
    }
  }
};

QTEST_GUILESS_MAIN(TestFixture)
#include "test_fixture.moc"
