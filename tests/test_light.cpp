// Light physics ("physics": "light"): no drone passes through a wall at the step limit (test_limits'
// layouts, head-on and at a slant), none is ever inside an obstacle of a forest, drones stay apart within
// the stated tolerance, the bytes do not depend on the thread count, a contact begins once per touching,
// the choice is recorded (config.json, the queue's summary.csv) and a bad value is refused; coverage
// matches Box2D's statistically.
#include "common.hpp"
#include "wall_layouts.hpp"

#include <cmath>
#include <cstring>

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/grid.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

/// Flies at max speed along `heading` (with a large max force the velocity follows at once).
class Heading final : public Behavior {
 public:
  explicit Heading(double heading) : heading_(heading) {}
  Vec2 decide(const Perception& me, Rng&) override { return Vec2::polar(me.max_speed, heading_) - me.velocity; }

 private:
  double heading_;
};

/// Flies at max speed towards `goal`, so a swarm piles up on it.
class Towards final : public Behavior {
 public:
  explicit Towards(Vec2 goal) : goal_(goal) {}
  Vec2 decide(const Perception& me, Rng&) override {
    const Vec2 to = goal_ - me.position;
    return (to.length() > 1e-9 ? to.with_length(me.max_speed) : Vec2{}) - me.velocity;
  }

 private:
  Vec2 goal_;
};

/// Flies along x (`sign` +1 or −1) for `on` s, back for `off` s, and again.
class Shuttle final : public Behavior {
 public:
  Shuttle(double sign, double on, double off) : sign_(sign), on_(on), off_(off) {}
  void prepare(const WorldView& world) override { time_ = world.time(); }
  Vec2 decide(const Perception& me, Rng&) override {
    const bool back = time_ >= on_ && time_ < on_ + off_;
    return Vec2{(back ? -sign_ : sign_) * me.max_speed, 0} - me.velocity;
  }

 private:
  double sign_, on_, off_, time_ = 0;
};

/// Records every contact between drones or with walls.
class Recorder final : public ContactHandler {
 public:
  std::vector<ContactEvent> events;
  void on_contact(const ContactEvent& e, ContactActions&) override {
    if (e.kind != ContactKind::target_in_view) events.push_back(e);
  }
};

/// Counts the contacts between drones that begin in each step.
class DroneContacts final : public ContactHandler {
 public:
  std::size_t count = 0;
  void on_contact(const ContactEvent& e, ContactActions&) override { count += e.kind == ContactKind::drone_drone; }
};

GroupSetup group_at(const char* name, Vec2 spawn, std::shared_ptr<Behavior> behavior, const DroneConfig& drone, std::size_t drones = 1) {
  GroupSetup g;
  g.name = name;
  g.drone = drone;
  g.drones = drones;
  g.spawn = spawn;
  g.spawn_radius = 1e-9;
  g.behavior = std::move(behavior);
  return g;
}

/// The deepest overlap between two flying drones as a fraction of their radii's sum (brute force).
double worst_overlap(const Simulation& sim) {
  const auto p = sim.drone_positions();
  double worst = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double need = sim.drone_config(sim.drone_groups()[i]).radius + sim.drone_config(sim.drone_groups()[j]).radius;
      worst = std::max(worst, (need - distance(p[i], p[j])) / need);
    }
  return worst;
}

/// Flies `setup`'s crowd to (100, 100) for 20 s: over 300 drones end within `near_radius` of it (the
/// crowd really presses) and no two overlap more than 2 % of their radii's sum in the last 10 s.
void expect_packed_and_apart(const SimulationSetup& setup, double near_radius) {
  Simulation sim(setup);
  double worst = 0;
  for (int s = 0; s < 1200; ++s) {
    sim.step();
    if (s >= 600) worst = std::max(worst, worst_overlap(sim));
  }
  std::size_t near = 0;
  for (Vec2 p : sim.drone_positions()) near += distance(p, {100, 100}) < near_radius;
  QVERIFY2(near > 300, qPrintable(QString("only %1 drones near the point").arg(near)));
  qInfo("deepest overlap in the crowd: %.4f of the radii's sum", worst);
  QVERIFY2(worst <= 0.02, qPrintable(QString("overlap %1 of the radii's sum").arg(worst)));
}

}  // namespace

class TestLight : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

  SimulationSetup setup_of(const std::string& json) const { return make_setup(parse_test(json, "light.json", *host_), *host_); }

 private Q_SLOTS:
  // test_limits' proof for Box2D, in light mode: at the step limit, a drone flying straight at a wall (a
  // map line, a solid polygon, a polygon thinner than a millimetre), head-on or at a slant (sliding),
  // never gets its centre past it, whatever the gap it starts from, and ends resting against it.
  void never_passes_a_wall_data() {
    QTest::addColumn<double>("radius");
    QTest::addColumn<double>("speed");
    QTest::addColumn<double>("dt");
    QTest::addColumn<int>("wall");  // 0 line, 1 polygon, 2 thin polygon
    QTest::addColumn<int>("lag");
    QTest::addColumn<double>("heading");
    const char* walls[] = {"line", "polygon", "thin polygon"};
    for (int wall = 0; wall < 3; ++wall)
      for (int lag = 0; lag < 2; ++lag)
        for (double heading : {0.0, 1.2}) {
          QTest::addRow("radius 1 m, 1 m per step, %s, lag %d, heading %.1f", walls[wall], lag, heading)
              << 1.0 << 60.0 << 1.0 / 60 << wall << lag << heading;
          QTest::addRow("radius 5 m, 2 m per step, %s, lag %d, heading %.1f", walls[wall], lag, heading)
              << 5.0 << 20.0 << 0.1 << wall << lag << heading;
          QTest::addRow("radius 0.3 m, 0.3 m per step, %s, lag %d, heading %.1f", walls[wall], lag, heading)
              << 0.3 << 300.0 << 0.001 << wall << lag << heading;
        }
  }
  void never_passes_a_wall() {
    QFETCH(double, radius);
    QFETCH(double, speed);
    QFETCH(double, dt);
    QFETCH(int, wall);
    QFETCH(int, lag);
    QFETCH(double, heading);
    SimulationSetup setup = wall_layout(wall, 1000, radius, speed, dt, lag, std::make_shared<Heading>(heading));
    setup.physics = PhysicsMode::light;
    QVERIFY(!check_drone(setup.groups[0].drone, dt));
    const double step = speed * dt;
    for (int k = 0; k <= 40; ++k) {  // gaps from all but touching to one step and a little more
      const double gap = 0.001 + (step + 0.05) * k / 40;
      setup.map.spawn = {x_wall - radius - gap, 100};
      Simulation sim(setup);
      for (int s = 0; s < 40; ++s) {
        sim.step();
        const double x = sim.drone_positions()[0].x;
        QVERIFY2(x <= x_wall - radius * (1 - 1e-9),
                 qPrintable(QString("gap %1 m: step %2 put the centre at x = %3").arg(gap).arg(s).arg(x, 0, 'g', 17)));
      }
      const double x = sim.drone_positions()[0].x;
      QVERIFY2(x > x_wall - radius - 1e-6, qPrintable(QString("gap %1 m: not resting against the wall (x = %2)").arg(gap).arg(x)));
      if (heading != 0) {  // slid along it at the speed along the wall
        QVERIFY2(sim.drone_positions()[0].y > 100 + 20 * step * std::sin(heading),
                 qPrintable(QString("gap %1 m: stuck at y = %2").arg(gap).arg(sim.drone_positions()[0].y)));
        QVERIFY(std::abs(sim.drone_velocities()[0].x) < 1e-9 * speed);  // its velocity into the wall is gone
      }
    }
  }

  // A swarm at the step limit in a dense forest, pressed into the trees by a goal beyond them: every
  // drone, every step, keeps its radius clear of every wall and outside every obstacle.
  void never_inside_an_obstacle_data() {
    QTest::addColumn<int>("lag");
    QTest::newRow("lag 0") << 0;
    QTest::newRow("lag 1") << 1;
  }
  void never_inside_an_obstacle() {
    QFETCH(int, lag);
    SimulationSetup setup = setup_of(R"({"behavior": "random_walk", "drones": 300, "physics": "light", "seed": 5,
        "drone": {"radius": 1, "max_speed": 60, "max_force": 1000},
        "map": {"name": "forest", "params": {"size": 300, "clusters": 40}}, "decision_lag": )" +
                                     std::to_string(lag) + "}");
    const Rect b = setup.map.bounds;
    setup.groups[0].behavior = std::make_shared<Towards>(Vec2{b.max.x, b.max.y});
    auto recorder = std::make_shared<Recorder>();
    setup.contact_handlers = {recorder};
    Simulation sim(setup);
    for (int s = 0; s < 300; ++s) {
      sim.step();
      const auto p = sim.drone_positions();
      for (std::uint32_t i = 0; i < p.size(); ++i)
        QVERIFY2(sim.geometry().is_free(p[i], 1 - 1e-6),
                 qPrintable(QString("step %1: drone %2 at (%3, %4) is within its radius of a wall").arg(s).arg(i).arg(p[i].x).arg(p[i].y)));
    }
    const auto walls = std::count_if(recorder->events.begin(), recorder->events.end(),
                                     [](const ContactEvent& e) { return e.kind == ContactKind::drone_obstacle; });
    QVERIFY2(walls > 100, qPrintable(QString("only %1 wall contacts: the walls were not tested").arg(walls)));
  }

  // 400 drones all flying at max speed to one point pile up around it: no two overlap by more than the
  // tolerance docs/architecture.md states (2 % of their radii's sum; Jacobi passes instead of
  // Gauss–Seidel left 75 %), and without the separation they would all sit on the point.
  void drones_keep_apart() {
    SimulationSetup setup;
    setup.physics = PhysicsMode::light;
    setup.map.bounds = {{0, 0}, {200, 200}};
    setup.map.spawn = {100, 100};
    setup.groups[0].drone = racer(1, 10);
    setup.groups[0].drones = 400;
    setup.groups[0].spawn_mode = SpawnMode::uniform;
    setup.groups[0].behavior = std::make_shared<Towards>(Vec2{100, 100});
    expect_packed_and_apart(setup, 25);
  }

  // A pile of two drone sizes (and masses) keeps the same tolerance as one size: 200 of each flying to
  // one point. Measured before the fix: 3.0–3.9 % of the radii's sum, against 0.4 % for one size.
  void mixed_sizes_keep_apart_data() {
    QTest::addColumn<double>("big_radius");
    QTest::addColumn<double>("big_mass");
    QTest::newRow("small and large") << 2.5 << 12.0;
    QTest::newRow("small and medium") << 1.5 << 4.0;
    QTest::newRow("two radii, one mass") << 2.5 << 1.5;
    QTest::newRow("one radius, two masses") << 1.0 << 12.0;
  }
  void mixed_sizes_keep_apart() {
    QFETCH(double, big_radius);
    QFETCH(double, big_mass);
    SimulationSetup setup;
    setup.physics = PhysicsMode::light;
    setup.map.bounds = {{0, 0}, {200, 200}};
    setup.map.spawn = {100, 100};
    setup.groups[0].drone = racer(1, 10);
    setup.groups[0].drones = 200;
    setup.groups[0].spawn_mode = SpawnMode::uniform;
    setup.groups[0].behavior = std::make_shared<Towards>(Vec2{100, 100});
    setup.groups.push_back(setup.groups[0]);
    setup.groups[1].drone = racer(big_radius, 10);
    setup.groups[1].drone.mass = big_mass;
    expect_packed_and_apart(setup, 50);
  }

  // 20,000 drones of radius 1 m in a 10 m map (the room check refuses such a test; a SimulationSetup
  // skips it), pressed to the middle: each touches about 1,200 others, 24 million pairs. Each drone keeps
  // its nearest neighbours up to the cap (about 120 for one size), so the contacts begun, the kept pairs
  // still touching after the first step's pushes, stay within 130 per drone (without the cap the pushes
  // went over every pair, and the pairs alone took gigabytes at 10^5 drones).
  void an_overfull_pile_keeps_its_pairs_bounded() {
    SimulationSetup setup;
    setup.physics = PhysicsMode::light;
    setup.map.bounds = {{0, 0}, {10, 10}};
    setup.map.spawn = {5, 5};
    setup.groups[0].drone = racer(1, 10);
    setup.groups[0].drones = 20'000;
    setup.groups[0].spawn_mode = SpawnMode::uniform;
    setup.groups[0].behavior = std::make_shared<Towards>(Vec2{5, 5});
    auto contacts = std::make_shared<DroneContacts>();
    setup.contact_handlers = {contacts};
    Simulation sim(setup);
    sim.step();
    const std::size_t n = setup.groups[0].drones;
    // The pile as it is: the pairs closer than their radii's sum (2 m), by a grid.
    PointGrid grid;
    grid.build(sim.drone_positions(), 2);
    std::size_t touching = 0;
    for (std::uint32_t i = 0; i < n; ++i) grid.query(sim.drone_positions()[i], 2, [&](std::uint32_t j, Vec2, double) { touching += j > i; });
    qInfo("%zu pairs touching, %zu contacts begun", touching, contacts->count);
    QVERIFY2(touching > 500 * n, qPrintable(QString::number(touching)));  // the pile is far fuller than the cap
    QVERIFY2(contacts->count > n && contacts->count <= 130 * n, qPrintable(QString::number(contacts->count)));
    sim.step();  // and goes on
    QCOMPARE(sim.drone_positions().size(), n);
  }

  // The same run on 1 and 2 threads (enough drones that the light physics splits them into tasks):
  // positions, velocities and every contact event byte-identical, both lags.
  void same_bytes_on_any_thread_count_data() { never_inside_an_obstacle_data(); }
  void same_bytes_on_any_thread_count() {
    QFETCH(int, lag);
    struct Run {
      std::vector<Vec2> positions, velocities;
      std::vector<ContactEvent> events;
    };
    auto run = [&](int threads) {
      SimulationSetup setup = setup_of(R"({"behavior": "random_walk", "drones": 1500, "physics": "light", "seed": 9,
          "drone": {"radius": 1, "max_speed": 30, "max_force": 1000}, "spawn": {"mode": "disc", "radius": 60},
          "map": {"name": "forest", "params": {"size": 300, "clusters": 20}}})");
      setup.threads = threads;
      setup.decision_lag = lag;
      auto recorder = std::make_shared<Recorder>();
      setup.contact_handlers = {recorder};
      Simulation sim(setup);
      sim.run_steps(90);
      return Run{{sim.drone_positions().begin(), sim.drone_positions().end()},
                 {sim.drone_velocities().begin(), sim.drone_velocities().end()},
                 recorder->events};
    };
    const Run one = run(1), two = run(2);
    QVERIFY2(one.events.size() > 1000, qPrintable(QString::number(one.events.size())));  // crowded: many contacts to order
    QCOMPARE(one.positions.size(), two.positions.size());
    QVERIFY(std::memcmp(one.positions.data(), two.positions.data(), one.positions.size() * sizeof(Vec2)) == 0);
    QVERIFY(std::memcmp(one.velocities.data(), two.velocities.data(), one.velocities.size() * sizeof(Vec2)) == 0);
    QCOMPARE(one.events.size(), two.events.size());
    for (std::size_t k = 0; k < one.events.size(); ++k) {
      const ContactEvent &a = one.events[k], &b = two.events[k];
      QVERIFY(a.kind == b.kind && a.drone == b.drone && a.other == b.other && a.time == b.time);
      QVERIFY(std::memcmp(&a.position, &b.position, sizeof(Vec2)) == 0);
    }
  }

  // Two drones fly head-on into each other and stay pressed together for a while, one presses against a
  // wall: one contact each. Drones that part and meet again, and a drone that leaves the wall and comes
  // back, begin a second contact. (Two frictionless discs pressed head-on for long slide off each
  // other, as the smallest offset grows: a contact that ends.)
  void contacts_begin_once_per_touching() {
    auto run = [&](double on, double off) {
      SimulationSetup setup;
      setup.physics = PhysicsMode::light;
      setup.map.bounds = {{0, 0}, {100, 100}};
      setup.map.lines = {{{80, 60}, {80, 100}}};  // the wall drone 2 flies into
      setup.map.spawn = {50, 50};
      const DroneConfig drone = racer(1, 5);
      setup.groups = {group_at("left", {40, 20}, std::make_shared<Shuttle>(1, on, off), drone),
                      group_at("right", {60, 20}, std::make_shared<Shuttle>(-1, on, off), drone),
                      group_at("wall", {70, 80}, std::make_shared<Shuttle>(1, on, off), drone)};
      auto recorder = std::make_shared<Recorder>();
      setup.contact_handlers = {recorder};
      Simulation sim(setup);
      sim.run_steps(8 * 60);
      return recorder->events;
    };
    auto count = [](const std::vector<ContactEvent>& events, ContactKind kind, std::uint32_t drone, std::uint32_t other) {
      return std::count_if(events.begin(), events.end(),
                           [&](const ContactEvent& e) { return e.kind == kind && e.drone == drone && (kind != ContactKind::drone_drone || e.other == other); });
    };
    const auto pressed = run(3, 100);  // pressed from 1.8 s to 3 s, then apart
    QCOMPARE(count(pressed, ContactKind::drone_drone, 0, 1), 1);
    QCOMPARE(count(pressed, ContactKind::drone_obstacle, 2, 0), 1);
    QCOMPARE(pressed.size(), std::size_t{2});
    const auto again = run(3, 2);  // pressed for 1 s, apart for 2 s, then together for the last 3 s
    QCOMPARE(count(again, ContactKind::drone_drone, 0, 1), 2);
    QCOMPARE(count(again, ContactKind::drone_obstacle, 2, 0), 2);
    for (const ContactEvent& e : again)  // positions: between the drones, or the drone's own
      if (e.kind == ContactKind::drone_drone) QVERIFY(std::abs(e.position.x - 50) < 1e-6 && std::abs(e.position.y - 20) < 1e-6);
      else QVERIFY(std::abs(e.position.x - 79) < 0.02);
  }

  // config.json says "physics": "light" only for light runs (a Box2D run's file is as before), the
  // queue's summary.csv gets the column, and a bad value is refused in one line naming the field and
  // the values allowed.
  void the_choice_is_recorded() {
    const std::string test = R"({"behavior": "random_walk", "drones": 5, "time": 2, "seed": 1)";
    const TestSpec light = parse_test(test + R"(, "physics": "light"})", "light.json", *host_);
    const TestSpec box2d = parse_test(test + "}", "box2d.json", *host_);
    QVERIFY(light.physics == PhysicsMode::light && box2d.physics == PhysicsMode::box2d);
    QVERIFY(resolved_json(light, *host_).find("\"physics\": \"light\"") != std::string::npos);
    QVERIFY(resolved_json(box2d, *host_).find("physics") == std::string::npos);
    QVERIFY(parse_test(test + R"(, "physics": "box2d"})", "box2d.json", *host_) == box2d);
    try {
      parse_test(test + R"(, "physics": "heavy"})", "heavy.json", *host_);
      QFAIL("heavy accepted");
    } catch (const InputError& e) {
      QCOMPARE(QString(e.what()), QString(R"(heavy.json: physics: "heavy" is not a physics (allowed: box2d, light))"));
    }
    QTemporaryDir dir;
    std::string queue = "[";
    queue += test;
    queue += R"(, "name": "b"}, )";
    queue += test;
    queue += R"(, "name": "l", "physics": "light"}])";
    QVERIFY(write_file(dir.filePath("q.json"), QByteArray::fromStdString(queue)));
    const CliResult r = run_salsa({"run", dir.filePath("q.json"), "--out", dir.filePath("out"), "--no-plots", "--quiet"});
    QVERIFY2(r.exit_code == 0, describe(r));
    const QStringList rows = QString(read_file(dir.filePath("out/summary.csv"))).split('\n', Qt::SkipEmptyParts);
    QCOMPARE(rows.size(), 3);
    const auto column = rows[0].split(',').indexOf("physics");
    QVERIFY(column >= 0);
    QCOMPARE(rows[1].split(',')[column], QString("box2d"));
    QCOMPARE(rows[2].split(',')[column], QString("light"));
  }

  // Box2D's float positions refuse a map beyond ±32,768 m for the paper's drone at 60 steps per second;
  // the light physics keeps doubles, so the scale workload's 1,000,000-drone map (63 km) runs, and
  // only a map beyond ±2^48 m is refused.
  void doubles_resolve_larger_maps() {
    const DroneConfig paper;
    const Rect big{{0, 0}, {63245.6, 63245.6}};
    QVERIFY(check_resolution(big, paper, 1.0 / 60));
    QVERIFY(!check_resolution(big, paper, 1.0 / 60, PhysicsMode::light));
    const Problem p = check_resolution({{0, 0}, {1e15, 1e15}}, paper, 1.0 / 60, PhysicsMode::light);
    QVERIFY2(QString::fromStdString(p.text()).contains("the light physics keeps positions as 64-bit doubles"), p.text().c_str());
    QVERIFY2(QString::fromStdString(p.text()).contains("within ±"), p.text().c_str());
  }

  // Coverage is what the experiments measure: on a small forest survey, the targets found in light mode
  // lie within Box2D mode's 95 % interval (8 paired seeds, t with 7 degrees of freedom), and the other
  // way round.
  void coverage_matches_box2d() {
    auto found = [&](PhysicsMode physics, int seed) {
      SimulationSetup setup = setup_of(R"({"behavior": "flocking", "drones": 10, "seed": )" + std::to_string(seed) + R"(,
          "map": {"name": "forest", "params": {"size": 300}}, "targets": {"kind": "tree", "count": 300, "params": {"radius": 5}}})");
      setup.physics = physics;
      Simulation sim(setup);
      sim.run_steps(60 * 60);
      return static_cast<double>(sim.targets_found());
    };
    auto interval = [](const std::vector<double>& v) {
      double mean = 0, var = 0;
      for (double x : v) mean += x / static_cast<double>(v.size());
      for (double x : v) var += (x - mean) * (x - mean) / static_cast<double>(v.size() - 1);
      const double half = 2.365 * std::sqrt(var / static_cast<double>(v.size()));
      return std::pair{mean - half, mean + half};
    };
    std::vector<double> box2d, light;
    for (int seed = 1; seed <= 8; ++seed) box2d.push_back(found(PhysicsMode::box2d, seed)), light.push_back(found(PhysicsMode::light, seed));
    const auto [b_lo, b_hi] = interval(box2d);
    const auto [l_lo, l_hi] = interval(light);
    const double b = (b_lo + b_hi) / 2, l = (l_lo + l_hi) / 2;
    qInfo("targets found: Box2D %.1f [%.1f, %.1f], light %.1f [%.1f, %.1f]", b, b_lo, b_hi, l, l_lo, l_hi);
    QVERIFY(l >= b_lo && l <= b_hi);
    QVERIFY(b >= l_lo && b <= l_hi);
  }
};

QTEST_GUILESS_MAIN(TestLight)
#include "test_light.moc"
