// Limits: every loop whose length depends on a user value ends quickly; the physics is only asked what
// it can do (a drone at max speed never passes through a wall, float positions resolve a drone's
// step); what plugins hand the core is checked like a user's input; huge swarms are announced.
#include "common.hpp"
#include "wall_layouts.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "salsa/core/model/simulation.hpp"
#include "salsa/core/model/static_geometry.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();

/// Flies straight along +x at max speed (with a large max force the velocity follows at once).
class Straight final : public Behavior {
 public:
  Vec2 decide(const Perception& me, Rng&) override { return Vec2{me.max_speed, 0} - me.velocity; }
};

/// Steers with a fixed vector, however large.
class Fixed final : public Behavior {
 public:
  explicit Fixed(Vec2 steering) : steering_(steering) {}
  Vec2 decide(const Perception&, Rng&) override { return steering_; }

 private:
  Vec2 steering_;
};

/// Trees of radius 1 m.
class Tree final : public TargetKind {
 public:
  double radius() const override { return 1; }
};

/// Credits every sighting to drone `drone`, which need not exist.
class Crediting final : public ContactHandler {
 public:
  explicit Crediting(std::uint32_t drone) : drone_(drone) {}
  void on_contact(const ContactEvent& e, ContactActions& actions) override {
    if (e.kind == ContactKind::target_in_view) actions.mark_found(e.other, drone_);
  }

 private:
  std::uint32_t drone_;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

class TestLimits : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();
  /// The built-in plugins and the test plugins that hand the core bad data.
  std::unique_ptr<PluginHost> bad_host_ = [] {
    auto host = std::make_unique<PluginHost>();
    host->load({{test_plugins_dir() / "bad-map", "test"}, {test_plugins_dir() / "bad-target", "test"},
                {test_plugins_dir() / "bad-behavior", "test"}, {plugin_dir(), "test"}});
    return host;
  }();

  /// make_setup's InputError for a test, or "" when it is accepted.
  static QString refusal(const std::string& json, const PluginHost& host) {
    try {
      make_setup(parse_test(json, "limits.json", host), host);
    } catch (const InputError& e) {
      return QString::fromStdString(e.what());
    }
    return {};
  }

 private Q_SLOTS:
  // ---------------------------------------------------------------- loops bounded by user values

  // The nearest-neighbour search widened its radius from the detection range by ×4: from 0, forever.
  void detection_range_zero_runs() {
    SimulationSetup setup;
    setup.map.bounds = {{0, 0}, {300, 300}};
    setup.map.spawn = {150, 150};
    setup.groups[0].drone.detection_range = 0;
    setup.groups[0].drones = 40;
    setup.groups[0].behavior = std::make_shared<Straight>();
    Simulation sim(setup);
    sim.run_steps(5);
    const auto got = sim.nearest_neighbour_distances();
    const auto pos = sim.drone_positions();
    for (std::size_t i = 0; i < pos.size(); ++i) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < pos.size(); ++j)
        if (j != i) best = std::min(best, distance(pos[i], pos[j]));
      QCOMPARE(got[i], best);
    }
  }

  void point_grid_cells_are_bounded_data() {
    QTest::addColumn<double>("cell");
    QTest::addColumn<double>("spread");
    QTest::addColumn<bool>("nan_first");
    QTest::newRow("cell 0") << 0.0 << 1000.0 << false;
    QTest::newRow("tiny cell, huge spread") << 1e-9 << 1e9 << false;
    QTest::newRow("NaN cell size") << not_a_number << 1000.0 << false;
    QTest::newRow("a NaN point first") << 10.0 << 1000.0 << true;
  }
  void point_grid_cells_are_bounded() {
    QFETCH(double, cell);
    QFETCH(double, spread);
    QFETCH(bool, nan_first);
    Rng rng(7, 0);
    std::vector<Vec2> points;
    if (nan_first) points.push_back({not_a_number, 1});
    for (int i = 0; i < 500; ++i) points.push_back(rng.in_rect({{0, 0}, {spread, spread}}));
    points.push_back({3, not_a_number});
    PointGrid grid;
    grid.build(points, cell);
    const double c = grid.cell_size();
    QVERIFY2((spread / c + 1) * (spread / c + 1) <= 4.0 * static_cast<double>(points.size()) + 64,
             qPrintable(QString("cell %1 m over %2 m").arg(c).arg(spread)));
    for (int q = 0; q < 50; ++q) {  // radius queries equal brute force; NaN points are never found
      const Vec2 p = rng.in_rect({{0, 0}, {spread, spread}});
      const double r = spread / 20;
      std::vector<std::uint32_t> got, want;
      grid.query(p, r, [&](std::uint32_t i, Vec2, double) { got.push_back(i); });
      for (std::uint32_t i = 0; i < points.size(); ++i)
        if (distance_squared(points[i], p) < r * r) want.push_back(i);
      std::sort(got.begin(), got.end());
      QCOMPARE(got, want);
    }
  }

  // Each segment was filed by testing every cell of its bounding box: a long diagonal cost ~10^6 cells.
  // Now it costs its length in cells. Counted, not timed, so busy machines and sanitizers agree.
  void long_diagonals_index_quickly() {
    MapData map;
    map.bounds = {{0, 0}, {1e5, 1e5}};
    map.spawn = {5e4, 5e4};
    Rng rng(1, 0);
    for (int i = 0; i < 500; ++i)
      map.lines.push_back({rng.in_rect({{0, 0}, {1e4, 1e4}}), rng.in_rect({{9e4, 9e4}, {1e5, 1e5}})});
    const StaticGeometry g(map, 1);
    const double cell = 1e5 / 1024;  // the grid's cell: at most 1024 cells a side
    double along = 0, boxes = 0;     // cells along each segment, cells in its bounding box
    for (const Segment& s : g.segments()) {
      const double w = std::abs(s.b.x - s.a.x) / cell + 1, h = std::abs(s.b.y - s.a.y) / cell + 1;
      along += w + h;
      boxes += w * h;
    }
    const auto examined = static_cast<double>(g.cells_examined());
    QVERIFY2(examined <= 6 * along && examined < boxes / 50,
             qPrintable(QString("%1 cells examined; %2 along the segments, %3 in their boxes")
                            .arg(examined).arg(along).arg(boxes)));
    // Still right: a ray across the map meets a diagonal exactly where the brute force does.
    std::vector<std::uint32_t> ids;
    for (int q = 0; q < 200; ++q) {
      const Vec2 from = rng.in_rect(map.bounds), dir = Vec2::polar(1, rng.angle());
      g.candidates(from, 3000, ids);
      std::optional<double> best;
      for (const Segment& s : g.segments())
        if (auto t = ray_segment(from, dir, 3000, s); t && (!best || *t < *best)) best = t;
      const auto hit = g.ray_cast(from, dir, 3000, ids);
      QCOMPARE(hit.has_value(), best.has_value());
      if (hit) QCOMPARE(hit->distance, *best);
    }
  }

  // Each drone tried up to 1,000,000 random points: with almost no free space, minutes per swarm.
  void spawning_in_a_tiny_pocket_ends_quickly_data() {
    QTest::addColumn<int>("mode");
    QTest::newRow("uniform") << int(SpawnMode::uniform);
    QTest::newRow("disc") << int(SpawnMode::disc);
  }
  void spawning_in_a_tiny_pocket_ends_quickly() {
    QFETCH(int, mode);
    SimulationSetup setup;
    setup.map.bounds = {{0, 0}, {100, 100}};
    setup.map.spawn = {50, 50};
    // Everything is solid but a 4 m × 4 m pocket; a drone of radius 1.99 m fits in a 2 cm square of it.
    setup.map.obstacles = {{{0, 0}, {48, 0}, {48, 100}, {0, 100}}, {{52, 0}, {100, 0}, {100, 100}, {52, 100}},
                           {{48, 0}, {52, 0}, {52, 48}, {48, 48}}, {{48, 52}, {52, 52}, {52, 100}, {48, 100}}};
    setup.groups[0].drone.radius = 1.99;
    setup.groups[0].spawn_mode = static_cast<SpawnMode>(mode);
    setup.groups[0].drones = 1000;
    setup.groups[0].behavior = std::make_shared<Straight>();
    const auto start = std::chrono::steady_clock::now();
    Simulation sim(setup);
    QVERIFY2(seconds_since(start) < 30, qPrintable(QString("%1 s").arg(seconds_since(start))));
    for (Vec2 p : sim.drone_positions()) QVERIFY(sim.is_free(p, setup.groups[0].drone.radius));
  }

  // The default disc (drones × radius) of 20,000 drones is 20 km wide; on a 200 m map every drone
  // outside the walls was clamped onto them, thousands onto the same corner points (a 100,000-drone
  // test on a 6 km map ran out of memory). The disc now stops at the farthest corner: centred, it
  // clamps drones onto the edges but never two onto one corner point.
  void a_default_disc_wider_than_the_map_spreads_the_drones() {
    SimulationSetup setup;
    setup.map.bounds = {{0, 0}, {200, 200}};
    setup.map.spawn = {100, 100};
    setup.groups[0].drones = 20000;
    setup.groups[0].drone.radius = 0.2;
    setup.groups[0].behavior = std::make_shared<Straight>();
    Simulation sim(setup);
    std::vector<Vec2> positions(sim.drone_positions().begin(), sim.drone_positions().end());
    std::size_t inside = 0;
    for (Vec2 p : positions) inside += p.x > 0.2 && p.x < 199.8 && p.y > 0.2 && p.y < 199.8;
    QVERIFY2(inside > positions.size() / 2, qPrintable(QString("%1 of %2 drones off the walls").arg(inside).arg(positions.size())));
    std::sort(positions.begin(), positions.end(), [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    QVERIFY(std::adjacent_find(positions.begin(), positions.end()) == positions.end());  // no two on one point
  }

  // (30 s: a bound against the minutes these took, loose enough for a busy sanitizer build.)
  // Targets that cannot fit were tried 1000 × (count + 10) times, then placed inside obstacles silently.
  void targets_that_cannot_fit_are_refused() {
    const auto start = std::chrono::steady_clock::now();
    const QString why = refusal(R"({"behavior": "random_walk", "map": {"name": "empty", "params": {"size": 100}},
                                    "targets": {"kind": "tree", "count": 1000000, "params": {"radius": 60}}})",
                                *host_);
    QVERIFY2(seconds_since(start) < 30, qPrintable(QString("%1 s").arg(seconds_since(start))));
    QVERIFY2(why.contains("limits.json: target kind 'tree' (plugin tree, ") && why.contains("libtree.so): room for only 0 of 1000000 targets of radius 60 m"),
             qPrintable(why));
  }

  // ---------------------------------------------------------------- physics

  void step_limit_data() {
    QTest::addColumn<double>("radius");
    QTest::addColumn<double>("speed");
    QTest::addColumn<double>("dt");
    QTest::addColumn<QString>("expected");  // "" when allowed
    QTest::newRow("paper drone") << 1.0 << 10.0 << 1.0 / 60 << "";
    QTest::newRow("at the radius") << 1.0 << 60.0 << 1.0 / 60 << "";
    QTest::newRow("at Box2D's 2 m") << 5.0 << 20.0 << 0.1 << "";
    QTest::newRow("1000 m/s") << 1.0 << 1000.0 << 1.0 / 60
                              << "drone.max_speed: 1000 m/s × dt 0.0166667 s = 16.7 m per step, more than the drone's radius 1 m, so "
                                 "it could pass through a wall between two contact checks (allowed: max_speed ≤ 60 m/s at this dt, "
                                 "or dt ≤ 0.001 s at this max_speed)";
    QTest::newRow("large drone, dt 1 s") << 10.0 << 3.0 << 1.0
                                         << "drone.max_speed: 3 m/s × dt 1 s = 3 m per step, more than the 2 m Box2D moves a body "
                                            "per step (allowed: max_speed ≤ 2 m/s at this dt, or dt ≤ 0.6666 s at this max_speed)";
    QTest::newRow("tiny drone") << 0.01 << 10.0 << 1.0 / 60
                                << "= 0.167 m per step, more than the drone's radius 0.01 m";
  }
  void step_limit() {
    QFETCH(double, radius);
    QFETCH(double, speed);
    QFETCH(double, dt);
    QFETCH(QString, expected);
    const Problem p = check_drone(racer(radius, speed), dt);
    if (expected.isEmpty()) QVERIFY2(!p, p.text().c_str());
    else QVERIFY2(QString::fromStdString(p.text()).contains(expected), p.text().c_str());
  }

  // The rule's proof: at the limit, a drone flying at max speed straight at a wall (a map line, a solid
  // polygon, a polygon thinner than a millimetre) never gets its centre past it, whatever the gap it
  // starts from, and ends resting against it.
  void drone_at_the_limit_never_passes_a_wall_data() {
    QTest::addColumn<double>("radius");
    QTest::addColumn<double>("speed");
    QTest::addColumn<double>("dt");
    QTest::addColumn<int>("wall");  // 0 line, 1 polygon, 2 thin polygon
    QTest::addColumn<int>("lag");
    const char* walls[] = {"line", "polygon", "thin polygon"};
    for (int wall = 0; wall < 3; ++wall)
      for (int lag = 0; lag < 2; ++lag) {
        QTest::addRow("radius 1 m, 1 m per step, %s, lag %d", walls[wall], lag) << 1.0 << 60.0 << 1.0 / 60 << wall << lag;
        QTest::addRow("radius 5 m, 2 m per step, %s, lag %d", walls[wall], lag) << 5.0 << 20.0 << 0.1 << wall << lag;
        QTest::addRow("radius 0.3 m, 0.3 m per step, %s, lag %d", walls[wall], lag) << 0.3 << 300.0 << 0.001 << wall << lag;
      }
  }
  void drone_at_the_limit_never_passes_a_wall() {
    QFETCH(double, radius);
    QFETCH(double, speed);
    QFETCH(double, dt);
    QFETCH(int, wall);
    QFETCH(int, lag);
    SimulationSetup setup = wall_layout(wall, 100, radius, speed, dt, lag, std::make_shared<Straight>());
    QVERIFY(!check_drone(setup.groups[0].drone, dt));
    const double step = speed * dt;
    for (int k = 0; k <= 40; ++k) {  // gaps from all but touching to one step and a little more
      const double gap = 0.001 + (step + 0.05) * k / 40;
      setup.map.spawn = {x_wall - radius - gap, 50};
      Simulation sim(setup);
      for (int s = 0; s < 40; ++s) {
        sim.step();
        const double x = sim.drone_positions()[0].x;
        QVERIFY2(x < x_wall, qPrintable(QString("gap %1 m: step %2 put the centre at x = %3").arg(gap).arg(s).arg(x)));
      }
      const double x = sim.drone_positions()[0].x;
      QVERIFY2(x > x_wall - radius - 0.05, qPrintable(QString("gap %1 m: never reached the wall (x = %2)").arg(gap).arg(x)));
      QVERIFY2(x < x_wall - radius + 0.05, qPrintable(QString("gap %1 m: not pushed back out (x = %2)").arg(gap).arg(x)));
    }
  }

  void float_resolution_limit() {
    const DroneConfig paper;  // 10 m/s
    const double dt = 1.0 / 60;
    QVERIFY(!check_resolution({{0, 0}, {32767, 32767}}, paper, dt));
    QVERIFY(!check_resolution({{-32767, 0}, {0, 100}}, paper, dt));
    const Problem p = check_resolution({{0, 0}, {32768, 100}}, paper, dt);
    QCOMPARE(QString::fromStdString(p.text()),
             "bounds: min [0, 0], max [32768, 100]: Box2D keeps positions as 32-bit floats, 0.00391 m apart at 32768 m, more "
             "than 2 % of a drone's step (max_speed 10 m/s × dt 0.0166667 s = 0.167 m), so drones would move in jumps or "
             "not at all (allowed: coordinates within ±32768 m at this max_speed and dt)");
    QVERIFY(check_resolution({{0, 0}, {1e12, 1e12}}, paper, dt));
    // A slower drone needs finer positions: the allowed size shrinks with the step.
    QVERIFY(QString::fromStdString(check_resolution({{0, 0}, {5000, 5000}}, racer(1, 0.1), dt).text()).contains("within ±512 m"));

    // Just inside the limit a drone still flies at its speed, within 1 %.
    SimulationSetup setup;
    setup.map.bounds = {{32000, 0}, {32767, 100}};
    setup.map.spawn = {32100, 50};
    setup.groups[0].drone = racer(1, 10);
    setup.groups[0].drone.max_force = 1000;
    setup.groups[0].drones = 1;
    setup.groups[0].spawn_radius = 1e-9;
    setup.groups[0].behavior = std::make_shared<Straight>();
    Simulation sim(setup);
    sim.run_steps(5);
    const double x0 = sim.drone_positions()[0].x;
    sim.run_steps(600);
    const double travelled = sim.drone_positions()[0].x - x0;
    QVERIFY2(std::abs(travelled - 100) <= 1, qPrintable(QString("%1 m in 10 s at 10 m/s").arg(travelled)));
  }

  void make_setup_checks_the_physics() {
    QVERIFY(refusal(R"({"behavior": "random_walk", "drone": {"max_speed": 1000}})", *host_)
                .startsWith("limits.json: drone.max_speed: 1000 m/s × dt 0.0166667 s = 16.7 m per step"));
    QVERIFY(refusal(R"({"behavior": "random_walk", "dt": 1, "drone": {"max_speed": 10}})", *host_)
                .startsWith("limits.json: drone.max_speed: 10 m/s × dt 1 s = 10 m per step"));
    QVERIFY(refusal(R"({"behavior": "random_walk", "map": {"name": "empty", "params": {"size": 1000000}}})", *host_)
                .startsWith("limits.json: map 'empty': bounds: min [0, 0], max [1000000, 1000000]: Box2D keeps positions as 32-bit floats"));
    QCOMPARE(refusal(R"({"behavior": "random_walk", "map": {"name": "empty", "params": {"size": 30000}}})", *host_), QString());
  }

  // ---------------------------------------------------------------- plugin data is input

  void bad_plugin_data_is_refused_data() {
    QTest::addColumn<QString>("json");
    QTest::addColumn<QString>("expected");
    const QString map = R"({"behavior": "random_walk", "map": {"name": "test_bad_map", "params": {"kind": %1}}})";
    QTest::newRow("map: NaN bounds") << map.arg(1) << "libtest_bad_map.so) returned bounds.max: [nan, 100] is not finite (allowed: finite corners";
    QTest::newRow("map: infinite point") << map.arg(2) << "libtest_bad_map.so) returned obstacles[0][1]: [inf, 10] is not finite";
    QTest::newRow("map: point outside") << map.arg(3) << "libtest_bad_map.so) returned obstacles[0][2]: [20, 120] is outside the bounds (min [0, 0], max [100, 100])";
    QTest::newRow("map: 2-point polygon") << map.arg(4) << "libtest_bad_map.so) returned obstacles[0]: polygon needs at least 3 points, got 2";
    QTest::newRow("map: NaN spawn") << map.arg(5) << "libtest_bad_map.so) returned spawn: [nan, 50] is not finite (allowed: a point in free space within the bounds)";
    QTest::newRow("map: 1-point line") << map.arg(6) << "libtest_bad_map.so) returned lines[0]: line needs at least 2 points, got 1";
    QTest::newRow("map: throws") << map.arg(7) << "libtest_bad_map.so) failed: no terrain today";
    QTest::newRow("map: NaN hollow point") << map.arg(9) << "libtest_bad_map.so) returned hollow[0][2]: [nan, 70] is not finite";
    const QString target = R"({"behavior": "random_walk", "map": {"name": "empty", "params": {"size": 100}},
                               "targets": {"kind": "test_bad_target", "count": 10, "params": {"kind": %1}}})";
    QTest::newRow("target: NaN position") << target.arg(1) << "libtest_bad_target.so): positions[9]: [nan, ";
    QTest::newRow("target: outside") << target.arg(2) << "libtest_bad_target.so): positions[9]: [110, 0] is outside the bounds (min [0, 0], max [100, 100])";
    QTest::newRow("target: radius -1") << target.arg(3) << "libtest_bad_target.so): radius: -1 m (allowed: a finite radius ≥ 0 m)";
    QTest::newRow("target: radius NaN") << target.arg(4) << "libtest_bad_target.so): radius: nan m";
    QTest::newRow("target: place throws") << target.arg(5) << "libtest_bad_target.so): lost the seed list";
    QTest::newRow("target: one too few") << target.arg(6) << "libtest_bad_target.so): positions: 9 placed for 10 targets asked for";
    QTest::newRow("target: infinite") << target.arg(7) << "libtest_bad_target.so): positions[9]: [";
  }
  void bad_plugin_data_is_refused() {
    QFETCH(QString, json);
    QFETCH(QString, expected);
    const QString why = refusal(json.toStdString(), *bad_host_);
    const QString plugin = json.contains("test_bad_map") ? "map 'test_bad_map' (plugin test_bad_map, " : "target kind 'test_bad_target' (plugin test_bad_target, ";
    QVERIFY2(why.startsWith("limits.json: " + plugin) && why.contains(expected) && !why.contains('\n'), qPrintable(why));
  }

  void huge_map_from_a_plugin_is_refused() {
    const QString why = refusal(R"({"behavior": "random_walk", "map": {"name": "test_bad_map", "params": {"kind": 8}}})", *bad_host_);
    QVERIFY2(why.startsWith("limits.json: map 'test_bad_map': bounds: min [0, 0], max [1000000000000, 1000000000000]: Box2D keeps positions"),
             qPrintable(why));
  }

  // Bad plugin data handed to a Simulation directly (the GUI's path) is refused too.
  void simulation_checks_what_it_is_given() {
    SimulationSetup setup;
    setup.map.bounds = {{0, 0}, {100, 100}};
    setup.map.spawn = {50, 50};
    setup.groups[0].behavior = std::make_shared<Straight>();
    auto refused = [](SimulationSetup s) {
      try {
        Simulation sim(std::move(s));
      } catch (const std::invalid_argument& e) {
        return QString::fromStdString(e.what());
      }
      return QString();
    };
    SimulationSetup s = setup;
    s.map.obstacles = {{{10, 10}, {not_a_number, 10}, {20, 20}}};
    QCOMPARE(refused(s), "map: obstacles[0][1]: [nan, 10] is not finite (allowed: a point within the bounds (min [0, 0], max [100, 100]))");
    s = setup;  // bounds whose extent is beyond a double: refused before any grid is sized from them
    s.map.bounds = {{-1e308, -1e308}, {1e308, 1e308}};
    s.map.spawn = {0, 0};
    QCOMPARE(refused(s), "map: bounds: min [-1e+308, -1e+308], max [1e+308, 1e+308] span inf × inf m, beyond a double "
                         "(allowed: max − min below 1.7e308 on both axes)");
    s = setup;
    s.groups[0].drone.detection_range = -1;
    QCOMPARE(refused(s), "drone.detection_range: -1 m is out of range (allowed: [0, 100000] m)");
    s = setup;
    s.dt = not_a_number;
    QCOMPARE(refused(s), "dt: nan s is out of range (allowed: a finite time step > 0 s)");
    s = setup;
    const auto& bad_target = bad_host_->target_kind("test_bad_target");
    ParameterValues nan_position(bad_target.factory.parameters);
    nan_position.set("kind", 1);
    s.target_kind = PluginHost::create(bad_target, nan_position);
    s.targets = 5;
    QVERIFY(refused(s).startsWith("positions[4]: [nan, "));
  }

  // A behavior steering NaN is a failure while running: exit status 1, one line naming it and the test.
  // A steering of any finite length clamps to max speed: (1e200, 0) once left the drone at speed 0
  // (its squared length overflowed).
  void huge_steering_clamps_to_max_speed() {
    for (const Vec2 steering : {Vec2{1e200, 0}, Vec2{-1e308, 1e308}, Vec2{0, 1.7e308}, Vec2{1e160, -1e160}}) {
      SimulationSetup setup;
      setup.map.bounds = {{0, 0}, {100, 100}};
      setup.map.spawn = {50, 50};
      setup.groups[0].drones = 3;
      setup.groups[0].drone.max_speed = 5;
      setup.groups[0].behavior = std::make_shared<Fixed>(steering);
      Simulation sim(setup);
      sim.run_steps(2);
      for (const Vec2 v : sim.drone_velocities()) {
        QVERIFY2(std::abs(v.length() - 5) < 1e-3, qPrintable(QString("speed %1 for steering (%2, %3)").arg(v.length()).arg(steering.x).arg(steering.y)));
        QVERIFY(v.normalized().dot(steering.normalized()) > 0.999);  // along the steering
      }
    }
    // The SDK's helpers alike, and their ordinary answers unchanged to the bit.
    QCOMPARE(Vec2(1e200, 0).clamped(5), Vec2(5, 0));
    QCOMPARE(Vec2(3e200, 4e200).length(), 5e200);
    QCOMPARE(Vec2(std::numeric_limits<double>::infinity(), 7).clamped(2), Vec2(2, 0));  // inf: its direction
    QCOMPARE(Vec2(1e200, 0).normalized(), Vec2(1, 0));
    QVERIFY(distance(Vec2(3e-200, 4e-200).normalized(), Vec2(0.6, 0.8)) < 1e-15);
    QVERIFY(std::isnan(Vec2(not_a_number, 1).clamped(2).x));  // NaN stays NaN: act refuses it, naming the drone
    Rng rng(9, 0);
    for (int i = 0; i < 10000; ++i) {
      const Vec2 v = Vec2::polar(rng.uniform(0, 20), rng.angle());
      const double m = rng.uniform(0.1, 10), l2 = v.x * v.x + v.y * v.y;
      const Vec2 old = l2 <= m * m ? v : v * (m / std::sqrt(l2));
      QVERIFY(v.clamped(m) == old);
      QVERIFY(v.length() == std::sqrt(l2));
      QVERIFY(l2 == 0 || v.normalized() == Vec2(v.x / std::sqrt(l2), v.y / std::sqrt(l2)));
    }
  }

  // A contact handler may credit only drones and targets that exist; else the test stops naming it.
  void contact_handler_ids_are_checked() {
    auto run = [](std::uint32_t drone) {
      SimulationSetup setup;
      setup.map.bounds = {{0, 0}, {100, 100}};
      setup.map.spawn = {50, 50};
      setup.groups[0].drones = 5;
      setup.groups[0].drone.camera_range = 200;  // every target in view at once
      setup.groups[0].behavior = std::make_shared<Straight>();
      setup.target_kind = std::make_shared<Tree>();
      setup.targets = 3;
      setup.contact_handlers = {std::make_shared<Crediting>(drone)};
      Simulation sim(setup);
      try {
        sim.run_steps(3);
      } catch (const PluginFailure& e) {
        return QString::fromStdString(e.kind + " " + std::to_string(e.index) + ": " + e.what());
      }
      return QString("found %1").arg(sim.targets_found());
    };
    QCOMPARE(run(4), QString("found 3"));
    QCOMPARE(run(4'000'000'000u), QString("contact handler 0: contact_handlers[0]: mark_found was given drone 4000000000, "
                                          "which does not exist (allowed: drone ids 0 to 4)"));
    QCOMPARE(run(5), QString("contact handler 0: contact_handlers[0]: mark_found was given drone 5, which does not exist "
                             "(allowed: drone ids 0 to 4)"));
  }

  void nan_steering_names_behavior_and_test() {
    QTemporaryDir dir;
    write_file(dir.filePath("nan.json"), R"({"behavior": {"name": "test_nan", "params": {"at": 0.1}}, "time": 1})");
    const CliResult r = run_salsa({"run", "nan.json", "--out", "out", "--plugin-dir", q(test_plugins_dir() / "bad-behavior")}, dir.path());
    QVERIFY2(!r.crashed && r.exit_code == 1, describe(r));
    const QStringList lines = non_empty_lines(r.err);
    QCOMPARE(lines.size(), 1);
    QVERIFY2(lines[0].contains("nan.json") && lines[0].contains("'test_nan'") &&
                 lines[0].contains("decide returned a non-finite steering [nan, 0] for drone 0"),
             describe(r));
  }

  // ---------------------------------------------------------------- huge swarms

  // A live change of the drone count meets the same room check as a test's start: 10,000 drones in a
  // 10 m map would start as one pile, every drone touching every other (n² contacts), so it is refused
  // and nothing changes; a count that fits is taken.
  void a_live_change_into_a_pile_is_refused() {
    for (const char* physics : {"box2d", "light"}) {
      const std::string json = std::string(R"({"behavior": "random_walk", "drones": 10, "map": {"name": "empty", "params": {"size": 10}}, "physics": ")") +
                               physics + "\"}";
      const TestSpec t = parse_test(json, "pile.json", *host_);
      Simulation sim(make_setup(t, *host_, 1));
      sim.step();
      try {
        sim.set_drone_count(10000);
        QFAIL("10,000 drones in a 10 m map were taken");
      } catch (const std::invalid_argument& e) {
        QVERIFY2(std::string(e.what()).starts_with("10,000 drones (bodies of ") && std::string(e.what()).find("do not fit on the map") != std::string::npos, e.what());
      }
      QCOMPARE(sim.drone_count(), std::size_t{10});
      sim.set_drone_count(12);
      sim.step();
      QCOMPARE(sim.flying_count(), std::size_t{12});
    }
  }

  void huge_swarm_is_announced() {
    const std::string json = R"({"behavior": "random_walk", "drones": 1000000, "drone": {"detection_range": 50},
                                 "map": {"name": "empty", "params": {"size": 2000}}, "time": 60})";
    const TestSpec t = parse_test(json, "swarm.json", *host_);
    const QString w = QString::fromStdString(workload_warning(t, make_setup(t, *host_)));
    QVERIFY2(w.startsWith("swarm.json: 1,000,000 drones with detection range 50 m on a 2000 m × 2000 m map: ~1,963 "
                          "neighbours per drone, about 1.2e+11 drone-neighbour checks per simulated second; 60 s simulated: "
                          "expect hours (about "),
             qPrintable(w));
    // A timed change that raises the drone count (or the detection range) is what the test will cost.
    const TestSpec grows = parse_test(R"({"behavior": "random_walk", "drones": 10, "drone": {"detection_range": 50},
                                          "map": {"name": "empty", "params": {"size": 2000}}, "time": 60,
                                          "changes": [{"time": 1, "set": {"drones": 1000000}}]})",
                                      "grows.json", *host_);
    const QString g = QString::fromStdString(workload_warning(grows, make_setup(grows, *host_)));
    QVERIFY2(g.startsWith("grows.json: 1,000,000 drones (after its timed changes) with detection range 50 m"), qPrintable(g));
    const TestSpec widens = parse_test(R"({"behavior": "random_walk", "drones": 10000, "drone": {"detection_range": 1},
                                           "map": {"name": "empty", "params": {"size": 2000}}, "time": 600,
                                           "changes": [{"time": 10, "set": {"drone.detection_range": 2000}}]})",
                                       "widens.json", *host_);
    QVERIFY2(workload_warning(widens, make_setup(widens, *host_)).find("after its timed changes") != std::string::npos,
             workload_warning(widens, make_setup(widens, *host_)).c_str());
    // Every example runs in minutes at most: no warning.
    for (const auto& entry : std::filesystem::directory_iterator(source_dir() / "examples"))
      if (entry.path().extension() == ".json")
        for (const TestSpec& e : load_tests(entry.path(), *host_))
          QVERIFY2(workload_warning(e, make_setup(e, *host_)).empty(), e.source.c_str());
  }
};

QTEST_GUILESS_MAIN(TestLimits)
#include "test_limits.moc"
