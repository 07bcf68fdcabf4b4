// Changing a live simulation (what the GUI's sandbox does): drone count, drone configuration, behavior,
// parameters, targets and map, each followed by more steps that must stay sound.
#include "common.hpp"

#include <cmath>

#include "salsa/core/simulation.hpp"
#include "salsa/core/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

class TestLiveChanges : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

  std::unique_ptr<Simulation> make(std::size_t drones) {
    const std::string json = R"({"behavior": "random_walk", "drones": )" + std::to_string(drones) +
                             R"(, "map": {"name": "forest", "params": {"size": 400}},
                                 "targets": {"kind": "tree", "count": 200}, "seed": 3})";
    return std::make_unique<Simulation>(make_setup(parse_test(json, "live", *host_), *host_, 2));
  }

  /// Every drone inside the bounds, out of solid obstacles, with a finite speed near max speed (a
  /// collision in the last physics step may push a drone a little past it; the next act clamps it).
  static void check_sound(const Simulation& sim) {
    const Rect b = sim.bounds();
    const double vmax = sim.drone_config().max_speed * 1.25;
    for (std::size_t i = 0; i < sim.drone_count(); ++i) {
      const Vec2 p = sim.drone_positions()[i], v = sim.drone_velocities()[i];
      QVERIFY2(b.contains(p), qPrintable(QString("drone %1 outside bounds").arg(i)));
      for (const auto& poly : sim.map().obstacles) QVERIFY(!inside_polygon(p, poly));
      QVERIFY(std::isfinite(v.x) && std::isfinite(v.y));
      QVERIFY2(v.length() <= vmax, qPrintable(QString("drone %1 at %2 m/s").arg(i).arg(v.length())));
    }
  }

 private Q_SLOTS:
  void drone_count_grows_and_shrinks() {
    auto sim = make(10);
    sim->run_steps(30);
    const Vec2 kept = sim->drone_positions()[3];
    sim->set_drone_count(25);
    QCOMPARE(sim->drone_count(), std::size_t(25));
    QCOMPARE(sim->drone_positions()[3], kept);  // existing drones stay where they are
    sim->run_steps(30);
    check_sound(*sim);
    sim->set_drone_count(4);
    QCOMPARE(sim->drone_count(), std::size_t(4));
    QCOMPARE(sim->drone_velocities().size(), std::size_t(4));
    sim->run_steps(30);
    check_sound(*sim);
  }

  void drone_config_changes_take_effect() {
    auto sim = make(12);
    sim->run_steps(20);
    DroneConfig slow = sim->drone_config();
    slow.max_speed = 2;
    slow.radius = 2;
    sim->set_drone_config(slow);
    QCOMPARE(sim->drone_count(), std::size_t(12));
    sim->run_steps(60);
    check_sound(*sim);
    double mean = 0;
    for (Vec2 v : sim->drone_velocities()) mean += v.length() / 12;
    QVERIFY2(mean <= 2.0, qPrintable(QString("mean speed %1 m/s").arg(mean)));
  }

  void behavior_and_parameters_change() {
    auto sim = make(20);
    sim->run_steps(20);
    const auto& flocking = host_->behavior("flocking");
    ParameterValues params(flocking.factory.parameters);
    sim->set_behavior(PluginHost::create(flocking, params));
    sim->run_steps(20);
    params.set("separation_distance", 30);
    sim->behavior().set_parameters(params);
    QCOMPARE(sim->behavior().param("separation_distance"), 30.0);
    sim->run_steps(20);
    check_sound(*sim);
  }

  void targets_and_map_change() {
    auto sim = make(15);
    sim->run_steps(60);
    const auto& tree = host_->target_kind("tree");
    sim->set_targets(PluginHost::create(tree, ParameterValues(tree.factory.parameters)), 50);
    QCOMPARE(sim->targets().size(), std::size_t(50));
    QCOMPARE(sim->targets_found(), std::size_t(0));
    sim->run_steps(30);
    check_sound(*sim);

    MapData map;
    map.bounds = {{0, 0}, {200, 100}};
    map.spawn = {20, 50};
    map.obstacles = {{{100, 20}, {120, 20}, {120, 80}, {100, 80}}};
    sim->set_map(map);
    QCOMPARE(sim->bounds(), map.bounds);
    QCOMPARE(sim->drone_count(), std::size_t(15));
    for (const auto& t : sim->targets()) QVERIFY(sim->is_free(t.position, 0));
    sim->run_steps(120);
    check_sound(*sim);
  }

  void map_with_blocked_spawn_is_refused() {
    auto sim = make(5);
    MapData map;
    map.bounds = {{0, 0}, {100, 100}};
    map.spawn = {50, 50};
    map.obstacles = {{{40, 40}, {60, 40}, {60, 60}, {40, 60}}};
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, sim->set_map(map));
  }
};

QTEST_GUILESS_MAIN(TestLiveChanges)
#include "test_live_changes.moc"
