// Changing a live simulation (what the GUI's sandbox does): drone count, drone configuration, behavior,
// parameters, targets and map, each followed by more steps that must stay sound.
#include "common.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

/// Steers at random; its reset and resize throw for more than `most` drones (a plugin failing a live change).
class Picky final : public BehaviorWithMemory<double> {
 public:
  explicit Picky(std::size_t most) : most_(most) {}
  void reset(std::size_t drones) override {
    if (drones > most_) throw std::runtime_error("too many drones");
    BehaviorWithMemory::reset(drones);
  }
  void resize(std::size_t drones) override {
    if (drones > most_) throw std::runtime_error("too many drones");
    BehaviorWithMemory::resize(drones);
  }
  Vec2 decide(const Perception& me, double& turns, Rng& rng) override {
    turns += 1;
    return Vec2::polar(me.max_force, rng.angle()) + avoid_obstacles(me);
  }

 private:
  std::size_t most_;
};

/// A contact handler that records its resets and checks the world of every event against them; its
/// reset throws for more than `most` drones.
class Watcher final : public ContactHandler {
 public:
  struct Reset {
    double dt, time;
    std::size_t drones;
    Rect bounds;
    double max_speed;
  };
  std::vector<Reset> resets;
  std::size_t sightings = 0;
  std::vector<std::string> problems;
  std::size_t most = 1'000'000;

  void reset(const WorldView& world) override {
    if (world.drone_positions().size() > most) throw std::runtime_error("too many drones");
    resets.push_back({world.dt(), world.time(), world.drone_positions().size(), world.bounds(), world.drone().max_speed});
  }
  void on_contact(const ContactEvent& e, ContactActions& actions) override {
    if (resets.empty()) return problems.push_back("an event before any reset");
    const WorldView& w = actions.world();
    if (w.time() != e.time) problems.push_back("world time " + std::to_string(w.time()) + " s for an event at " + std::to_string(e.time) + " s");
    if (w.dt() != resets.back().dt) problems.push_back("world dt " + std::to_string(w.dt()));
    if (w.drone_positions().size() != resets.back().drones) problems.push_back("drones " + std::to_string(w.drone_positions().size()));
    if (w.bounds() != resets.back().bounds) problems.push_back("other bounds");
    // A sighting counts at the end of its step: a whole number of steps after the last reset.
    const double steps = (e.time - resets.back().time) / w.dt();
    if (!(steps >= 0.999 && std::abs(steps - std::round(steps)) < 1e-6))
      problems.push_back("event time " + std::to_string(e.time) + " s is not the end of a step");
    sightings += e.kind == ContactKind::target_in_view;
  }
};

}  // namespace

class TestLiveChanges : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();
  std::unique_ptr<PluginHost> bad_host_ = [] {  // a target kind that hands the core bad data on request
    auto host = std::make_unique<PluginHost>();
    host->load({{test_plugins_dir() / "bad-target", "test"}});
    return host;
  }();

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
    // Fewer: the highest ids are removed, never reused; the others fly on where they were.
    const Vec2 before = sim->drone_positions()[3];
    sim->set_drone_count(4);
    QCOMPARE(sim->flying_count(), std::size_t(4));
    QCOMPARE(sim->drone_count(), std::size_t(25));
    QCOMPARE(sim->drone_positions()[3], before);
    for (std::uint32_t i = 0; i < 25; ++i) QCOMPARE(sim->drone_status()[i] == DroneStatus::removed, i >= 4);
    const Vec2 gone = sim->drone_positions()[10];
    sim->run_steps(30);
    QCOMPARE(sim->drone_positions()[10], gone);  // a removed drone moves no more
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

  // Contact handlers are reset with the world when a test starts and whenever drones are re-spawned or
  // targets re-placed, not for other changes; during an event their world is at the event's time.
  void contact_handlers_are_reset_with_the_world() {
    const std::string json = R"({"behavior": "random_walk", "drones": 15, "drone": {"base": "small", "camera_range": 60},
                                 "map": {"name": "forest", "params": {"size": 400}}, "targets": {"kind": "tree", "count": 200},
                                 "dt": 0.05, "seed": 3})";
    SimulationSetup setup = make_setup(parse_test(json, "live", *host_), *host_, 2);
    auto watcher = std::make_shared<Watcher>();
    setup.contact_handlers.push_back(watcher);  // after detect_targets
    Simulation sim(setup);
    QCOMPARE(watcher->resets.size(), std::size_t(1));
    QCOMPARE(watcher->resets[0].dt, 0.05);
    QCOMPARE(watcher->resets[0].time, 0.0);
    QCOMPARE(watcher->resets[0].drones, std::size_t(15));
    QCOMPARE(watcher->resets[0].bounds, sim.bounds());
    QCOMPARE(watcher->resets[0].max_speed, 10.0);
    sim.run_steps(40);
    QVERIFY2(watcher->sightings > 0, "no target was ever in view: the test shows nothing");

    auto last = [&] { return watcher->resets.back(); };
    sim.set_drone_count(20);
    QCOMPARE(watcher->resets.size(), std::size_t(2));
    QCOMPARE(last().drones, std::size_t(20));
    QCOMPARE(last().time, sim.time());
    sim.run_steps(10);
    const auto& tree = host_->target_kind("tree");
    sim.set_targets(PluginHost::create(tree, ParameterValues(tree.factory.parameters)), 50);
    QCOMPARE(watcher->resets.size(), std::size_t(3));
    sim.run_steps(10);
    MapData map;
    map.bounds = {{0, 0}, {200, 100}};
    map.spawn = {20, 50};
    sim.set_map(map);
    QCOMPARE(watcher->resets.size(), std::size_t(4));
    QCOMPARE(last().bounds, map.bounds);
    QCOMPARE(last().drones, std::size_t(20));
    // Other changes keep the handlers' state.
    sim.set_behavior(std::make_shared<Picky>(100));
    DroneConfig config = sim.drone_config();
    config.max_speed = 8;
    sim.set_drone_config(config);
    QCOMPARE(watcher->resets.size(), std::size_t(4));
    sim.run_steps(20);

    // A handler whose reset refuses the change leaves the simulation as it was.
    watcher->most = 25;
    const std::size_t before = watcher->resets.size();
    QVERIFY_THROWS_EXCEPTION(std::runtime_error, sim.set_drone_count(30));
    QCOMPARE(sim.drone_count(), std::size_t(20));
    QCOMPARE(watcher->resets.size(), before);
    sim.run_steps(5);
    check_sound(sim);
    QVERIFY2(watcher->problems.empty(), watcher->problems.empty() ? "" : watcher->problems.front().c_str());
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

  /// Two simulations of the same test, one of which will see a refused change.
  std::pair<std::unique_ptr<Simulation>, std::unique_ptr<Simulation>> twins() {
    const std::string json = R"({"behavior": "random_walk", "drones": 12, "map": {"name": "forest", "params": {"size": 300, "clusters": 12}},
                                 "targets": {"kind": "tree", "count": 300}, "seed": 5})";
    auto setup = [&] {
      SimulationSetup s = make_setup(parse_test(json, "twin", *host_), *host_, 1);
      s.groups[0].behavior = std::make_shared<Picky>(20);
      return s;
    };
    return {std::make_unique<Simulation>(setup()), std::make_unique<Simulation>(setup())};
  }

  /// Everything a step depends on or produces is the same in both.
  static void check_identical(const Simulation& a, const Simulation& b) {
    QCOMPARE(a.step_count(), b.step_count());
    QCOMPARE(a.drone_count(), b.drone_count());
    QVERIFY(std::ranges::equal(a.drone_positions(), b.drone_positions()));
    QVERIFY(std::ranges::equal(a.drone_velocities(), b.drone_velocities()));
    QVERIFY(std::ranges::equal(a.commanded_velocities(), b.commanded_velocities()));
    QCOMPARE(a.targets().size(), b.targets().size());
    for (std::size_t t = 0; t < a.targets().size(); ++t) {
      QCOMPARE(a.targets()[t].position, b.targets()[t].position);
      QCOMPARE(a.targets()[t].found_by, b.targets()[t].found_by);
      QCOMPARE(a.targets()[t].observations, b.targets()[t].observations);
    }
    QCOMPARE(a.targets_found(), b.targets_found());
    QCOMPARE(a.collisions(), b.collisions());
    QCOMPARE(a.bounds(), b.bounds());
    QCOMPARE(a.drone_config(), b.drone_config());
    QCOMPARE(a.spawn_point(), b.spawn_point());
  }

  // A refused live change throws and leaves the simulation exactly as it was: it then steps
  // byte-identically to a twin that never saw the call.
  void refused_change_leaves_no_trace_data() {
    QTest::addColumn<int>("change");
    QTest::newRow("map: spawn inside an obstacle") << 0;
    QTest::newRow("map: NaN point") << 1;
    QTest::newRow("map: too large for float positions") << 2;
    QTest::newRow("drone config: max_speed × dt too long") << 3;
    QTest::newRow("drone config: negative range") << 4;
    QTest::newRow("drone count: behavior reset throws") << 5;
    QTest::newRow("targets: NaN position") << 6;
    QTest::newRow("targets: place throws") << 7;
    QTest::newRow("targets: cannot fit") << 8;
    QTest::newRow("behavior: none") << 9;
    QTest::newRow("behavior: reset throws") << 10;
  }
  void refused_change_leaves_no_trace() {
    QFETCH(int, change);
    auto [sim, twin] = twins();
    sim->run_steps(40);
    twin->run_steps(40);
    check_identical(*sim, *twin);
    MapData map;
    map.bounds = {{0, 0}, {100, 100}};
    map.spawn = {50, 50};
    DroneConfig drone = sim->drone_config();
    auto bad_target = [&](int kind) {
      const auto& entry = bad_host_->target_kind("test_bad_target");
      ParameterValues values(entry.factory.parameters);
      values.set("kind", kind);
      return PluginHost::create(entry, values);
    };
    auto attempt = [&]() {
      switch (change) {
        case 0: map.obstacles = {{{40, 40}, {60, 40}, {60, 60}, {40, 60}}}; return sim->set_map(map);
        case 1: map.lines = {{{10, 10}, {std::nan(""), 20}}}; return sim->set_map(map);
        case 2: map.bounds.max = {1e9, 1e9}; return sim->set_map(map);
        case 3: drone.max_speed = 1000; return sim->set_drone_config(drone);
        case 4: drone.camera_range = -1; return sim->set_drone_config(drone);
        case 5: return sim->set_drone_count(30);
        case 6: return sim->set_targets(bad_target(1), 50);
        case 7: return sim->set_targets(bad_target(5), 50);
        case 8: {
          const auto& tree = host_->target_kind("tree");
          ParameterValues huge(tree.factory.parameters);
          huge.set("radius", 100);
          return sim->set_targets(PluginHost::create(tree, huge), 50);
        }
        case 9: return sim->set_behavior(nullptr);
        default: return sim->set_behavior(std::make_shared<Picky>(5));
      }
    };
    bool threw = false;
    try {
      attempt();
    } catch (const std::exception& e) {
      threw = true;
      qInfo("refused: %s", e.what());
    }
    QVERIFY(threw);
    check_identical(*sim, *twin);
    sim->run_steps(120);
    twin->run_steps(120);
    check_identical(*sim, *twin);
  }

  // Changing the drone configuration keeps the targets already found (it used to re-place them).
  void drone_config_change_keeps_found_targets() {
    auto sim = make(30);
    sim->run_steps(300);
    QVERIFY(sim->targets_found() > 0);
    const auto before = sim->targets();
    DroneConfig wider = sim->drone_config();
    wider.camera_range = 40;
    sim->set_drone_config(wider);
    QCOMPARE(sim->targets_found(), std::size_t(std::ranges::count_if(before, [](const TargetState& t) { return t.found(); })));
    for (std::size_t t = 0; t < before.size(); ++t) QCOMPARE(sim->targets()[t].found_by, before[t].found_by);
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
