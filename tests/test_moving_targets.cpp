// Moving targets: the built-in `walker` kind against its definition (its speed held, never inside an
// obstacle or out of bounds, turning away from them, the same paths for a seed whatever the drones do,
// other paths for another seed), sensing of fast movers against all pairs, targets.csv's columns for
// moving targets, and the core's refusals (a step longer than the radius, a move() out of contract).
#include <QtTest>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "common.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/model/simulation.hpp"

using namespace salsa_test;
using salsa::Vec2;

namespace {

/// Records the targets each drone perceives (decide may run on several threads: each drone its own slot).
class Recorder final : public salsa::Behavior {
 public:
  std::vector<std::vector<salsa::TargetSeen>> seen;
  void reset(std::size_t drones) override { seen.assign(drones, {}); }
  Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    seen[me.id].assign(me.targets.begin(), me.targets.end());
    return Vec2::polar(me.max_force, 0.7 * me.id + 0.4 * me.time);  // each drone turning its own way
  }
};

/// Targets running straight at `speed` m/s (far faster than people: the drones' lists of targets in
/// reach must follow them), bouncing off the map's edges; `stray` breaks the contract once.
class Sprinter final : public salsa::TargetKind {
 public:
  explicit Sprinter(double speed, bool stray = false) : speed_(speed), stray_(stray) {}
  double radius() const override { return 0.5; }
  bool moves() const override { return true; }
  double max_speed() const override { return speed_; }
  void move(std::span<Vec2> positions, std::span<Vec2> velocities, const salsa::WorldView& world, salsa::Rng& rng) const override {
    const salsa::Rect b = world.bounds();
    for (std::size_t i = 0; i < positions.size(); ++i) {
      if (velocities[i] == Vec2{}) velocities[i] = Vec2::polar(speed_, rng.angle());
      Vec2 next = positions[i] + velocities[i] * world.dt();
      if (next.x < b.min.x + 1 || next.x > b.max.x - 1) velocities[i].x = -velocities[i].x;
      if (next.y < b.min.y + 1 || next.y > b.max.y - 1) velocities[i].y = -velocities[i].y;
      next = positions[i] + velocities[i] * world.dt();
      if (world.is_free(next, radius())) positions[i] = next;
    }
    if (stray_ && world.time() > 0.5) positions[0] = positions[0] + Vec2{2 * speed_ * world.dt(), 0};  // too far
  }

 private:
  double speed_;
  bool stray_;
};

}  // namespace

class TestMovingTargets : public QObject {
  Q_OBJECT

  std::unique_ptr<salsa::PluginHost> host_;

  salsa::SimulationSetup setup_of(const QString& json) { return salsa::make_setup(salsa::parse_test(json.toStdString(), "t.json", *host_), *host_, 2); }
  /// A cluttered forest with `walkers` people walking at `speed` m/s among `drones` drones of `behavior`.
  salsa::SimulationSetup forest(double speed, const char* behavior, int drones, int seed, int walkers = 150) {
    return setup_of(QString(R"({"name": "t", "behavior": "%1", "drones": %2, "seed": %3, "time": 60,
                               "map": {"name": "forest", "params": {"size": 200, "cluster_density": 300}},
                               "targets": {"kind": "walker", "count": %4, "params": {"speed": %5}}})")
                        .arg(behavior).arg(drones).arg(seed).arg(walkers).arg(speed));
  }
  static std::vector<Vec2> positions(const salsa::Simulation& sim) {
    std::vector<Vec2> out;
    for (const auto& t : sim.targets()) out.push_back(t.position);
    return out;
  }

 private Q_SLOTS:
  void initTestCase() {
    host_ = builtin_host();
    QVERIFY(host_->failures().empty());
  }

  // Every step a walker goes exactly speed × dt or stays put (blocked), always on free ground inside the
  // bounds; it rarely stays put (it turns away before it meets an obstacle), and it wanders (its path
  // is longer than the distance it ends up from where it began).
  void walker_holds_its_speed_on_free_ground_data() {
    QTest::addColumn<double>("speed");
    QTest::newRow("0.5 m/s") << 0.5;
    QTest::newRow("1.5 m/s") << 1.5;
    QTest::newRow("3 m/s") << 3.0;
  }
  void walker_holds_its_speed_on_free_ground() {
    QFETCH(double, speed);
    salsa::Simulation sim(forest(speed, "random_walk", 4, 7));
    QVERIFY(sim.targets_move());
    const double radius = sim.setup().target_kind->radius(), step = speed * sim.dt();
    const std::vector<Vec2> start = positions(sim);
    std::size_t moved = 0, stayed = 0;
    for (int k = 0; k < 60 * 60; ++k) {
      const std::vector<Vec2> before = positions(sim);
      sim.step();
      for (std::size_t i = 0; i < before.size(); ++i) {
        const Vec2 p = sim.targets()[i].position;
        const double d = salsa::distance(before[i], p);
        QVERIFY2(d == 0 || std::abs(d - step) < 1e-9 * step,
                 qPrintable(QString("walker %1 went %2 m in a step (its speed: %3 m)").arg(i).arg(d, 0, 'g', 17).arg(step)));
        QVERIFY2(sim.is_free(p, radius), qPrintable(QString("walker %1 at (%2, %3) is not on free ground").arg(i).arg(p.x).arg(p.y)));
        ++(d == 0 ? stayed : moved);
      }
    }
    QVERIFY2(stayed * 100 < moved, qPrintable(QString("%1 of %2 walker-steps blocked").arg(stayed).arg(stayed + moved)));
    double straight = 0;
    for (std::size_t i = 0; i < start.size(); ++i) straight += salsa::distance(start[i], sim.targets()[i].position);
    QVERIFY2(straight / static_cast<double>(start.size()) < 0.8 * speed * 60, "walkers go straight: their heading does not wander");
    QVERIFY2(straight / static_cast<double>(start.size()) > 0.05 * speed * 60, "walkers stay where they were");
  }

  // The paths come from the seed alone: other behaviors and swarm sizes (which find other walkers at
  // other times) meet the same walkers in the same places; another seed, other paths.
  void walker_paths_depend_on_the_seed_alone() {
    auto run = [&](const char* behavior, int drones, int seed) {
      salsa::Simulation sim(forest(1.0, behavior, drones, seed));
      sim.run_steps(20 * 60);
      return std::make_pair(positions(sim), sim.targets_found());
    };
    const auto [walk, walk_found] = run("random_walk", 8, 3);
    const auto [flock, flock_found] = run("flocking", 20, 3);
    const auto [other, other_found] = run("random_walk", 8, 4);
    QVERIFY2(walk_found > 0 && flock_found > 0 && walk_found != flock_found, "the behaviors should find different numbers of walkers");
    QVERIFY(walk == flock);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < walk.size(); ++i) differ += walk[i] != other[i];
    QCOMPARE(differ, walk.size());
  }

  // Sensing follows fast movers: every step each drone perceives exactly the targets within camera
  // range + radius of it at the positions the targets had when it sensed (all pairs), at those
  // positions, in id order; found ones are found where they were then, and move on.
  void sensing_follows_moving_targets_data() {
    QTest::addColumn<int>("lag");
    QTest::newRow("decision lag 0") << 0;
    QTest::newRow("decision lag 1") << 1;
  }
  void sensing_follows_moving_targets() {
    QFETCH(int, lag);
    auto recorder = std::make_shared<Recorder>();
    salsa::SimulationSetup setup;
    setup.map.bounds = {{0, 0}, {300, 300}};
    setup.map.spawn = {150, 150};
    setup.groups[0].spawn_mode = salsa::SpawnMode::uniform;
    setup.groups[0].drones = 60;
    setup.groups[0].behavior = recorder;
    setup.target_kind = std::make_shared<Sprinter>(25.0);
    setup.targets = 400;
    const auto& handler = host_->contact_handler("detect_targets");
    setup.contact_handlers = {salsa::PluginHost::create(handler, salsa::ParameterValues(handler.factory.parameters))};
    setup.seed = 5;
    setup.threads = 2;
    setup.decision_lag = lag;
    salsa::Simulation sim(setup);
    const double reach = sim.drone_config().camera_range + 0.5;
    std::vector<Vec2> found_at(sim.targets().size(), Vec2{NAN, NAN});
    std::size_t seen = 0;
    for (int step = 0; step < 300; ++step) {
      const std::vector<Vec2> drones(sim.drone_positions().begin(), sim.drone_positions().end());
      const std::vector<Vec2> targets = positions(sim);
      sim.step();
      for (std::size_t i = 0; i < drones.size(); ++i) {
        std::vector<std::uint32_t> expected, got;
        for (std::uint32_t t = 0; t < targets.size(); ++t)
          if (salsa::distance(drones[i], targets[t]) < reach) {
            expected.push_back(t);
            if (std::isnan(found_at[t].x)) found_at[t] = targets[t];
          }
        for (const salsa::TargetSeen& t : recorder->seen[i]) {
          got.push_back(t.id);
          QCOMPARE(t.position, targets[t.id]);
        }
        QVERIFY2(got == expected, qPrintable(QString("step %1, drone %2: %3 targets perceived, all pairs %4")
                                                 .arg(step).arg(i).arg(got.size()).arg(expected.size())));
        seen += got.size();
      }
    }
    std::size_t found = 0, moved_on = 0;
    for (std::size_t t = 0; t < sim.targets().size(); ++t) {
      const salsa::TargetState& s = sim.targets()[t];
      QCOMPARE(s.found(), !std::isnan(found_at[t].x));
      if (!s.found()) continue;
      QCOMPARE(s.found_position, found_at[t]);
      ++found, moved_on += s.position != s.found_position;
    }
    QVERIFY2(seen > 1000 && found > 20, qPrintable(QString("%1 sightings, %2 found: too few to tell").arg(seen).arg(found)));
    QCOMPARE(moved_on, found);  // found is for good; the target runs on
  }

  // targets.csv: x, y where each walker ended; found_x, found_y where it was found (empty if never).
  void targets_csv_says_where_each_was_found() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), R"({"name": "t", "behavior": "random_walk", "drones": 8, "seed": 2, "time": 60,
        "map": {"name": "forest", "params": {"size": 150}}, "targets": {"kind": "walker", "count": 40, "params": {"speed": 1.5}}})"));
    const CliResult r = run_salsa({"run", dir.filePath("t.json"), "--out", dir.filePath("out"), "--no-plots"});
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto rows = rows_of(dir.filePath("out/t/targets.csv"));
    QCOMPARE(non_empty_lines(read_file(dir.filePath("out/t/targets.csv"))).value(0), QString("id,x,y,found_time,found_by,observations,found_x,found_y"));
    std::size_t found = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const auto& row = rows[k];
      QCOMPARE(row[3].empty(), row[6].empty());
      QCOMPARE(row[3].empty(), row[7].empty());
      if (row[3].empty()) continue;
      ++found;
      const double walked = std::hypot(std::stod(row[1]) - std::stod(row[6]), std::stod(row[2]) - std::stod(row[7]));
      QVERIFY2(walked <= 1.5 * (60 - std::stod(row[3])) + 1e-3, "a walker went farther than its speed allows since it was found");
    }
    QVERIFY2(found > 0, "no walker found: nothing tested");
  }

  // A time step in which a walker would go farther than its radius is refused in one line naming the
  // file, the kind and the allowed step (exit status 2); so is a move() that breaks the contract.
  void refusals() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), R"({"name": "t", "behavior": "random_walk", "drones": 2, "dt": 0.1, "time": 5,
        "map": {"name": "empty", "params": {"size": 100}}, "targets": {"kind": "walker", "count": 4, "params": {"speed": 3, "radius": 0.2}}})"));
    const CliResult r = run_salsa({"run", dir.filePath("t.json"), "--out", dir.filePath("out")});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("t.json") && r.err.contains("walker") && r.err.contains("dt: 0.1 s") && r.err.contains("at most 0.06666 s"),
             describe(r));

    salsa::SimulationSetup setup;
    setup.map.bounds = {{0, 0}, {100, 100}};
    setup.map.spawn = {50, 50};
    setup.groups[0].drones = 2;
    setup.groups[0].behavior = std::make_shared<Recorder>();
    setup.target_kind = std::make_shared<Sprinter>(5.0, true);
    setup.targets = 3;
    salsa::Simulation sim(setup);
    try {
      sim.run_steps(60);
      QFAIL("a target moved twice max_speed × dt and the core let it");
    } catch (const salsa::PluginFailure& e) {
      QCOMPARE(QString::fromStdString(e.kind), QString("target kind"));
      QVERIFY2(QString(e.what()).contains("move() took target 0") && QString(e.what()).contains("farther than max_speed × dt"), e.what());
    }
    setup.target_kind = std::make_shared<Sprinter>(15.0);
    salsa::Simulation fine(setup);
    try {
      fine.set_dt(0.05);  // 0.75 m a step, radius 0.5 m (the drones' limit: 1 m)
      QFAIL("a time step that lets a target go farther than its radius was taken");
    } catch (const std::invalid_argument& e) {
      QVERIFY2(QString(e.what()).startsWith("targets: dt: 0.05 s"), e.what());
    }
    fine.set_dt(1.0 / 30);  // 0.5 m a step
  }
};

QTEST_GUILESS_MAIN(TestMovingTargets)
#include "test_moving_targets.moc"
