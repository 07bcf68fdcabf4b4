// The built-in behaviors do what they are for, measured through real simulations with the real
// plugins: flocking aligns, dynamic space partitioning spreads out, pheromone avoidance covers more
// ground than a random walk, and no drone ever leaves the map or enters an obstacle.
#include <QtTest>

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <unordered_set>

#include "common.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/model/static_geometry.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa_test;
using salsa::Vec2;

namespace {

/// |mean of the unit velocities|: 1 when all drones fly the same way, about 1/sqrt(N) when random.
double polarisation(const salsa::Simulation& sim) {
  Vec2 sum;
  for (Vec2 v : sim.drone_velocities()) sum += v.normalized();
  return sum.length() / static_cast<double>(sim.drone_count());
}

double mean_nearest_neighbour(const salsa::Simulation& sim) {
  double sum = 0;
  for (double d : sim.nearest_neighbour_distances()) sum += d;
  return sum / static_cast<double>(sim.drone_count());
}

/// Area coverage: which part of the free map (5 m cells whose centre is clear of obstacles) has been
/// within camera range of some drone, sampled every 0.1 s (a drone moves at most 1 m in between).
class Coverage {
 public:
  explicit Coverage(const salsa::Simulation& sim) : b_(sim.bounds()), range_(sim.drone_config().camera_range) {
    cols_ = static_cast<int>(std::ceil(b_.width() / kCell)), rows_ = static_cast<int>(std::ceil(b_.height() / kCell));
    state_.assign(static_cast<std::size_t>(cols_) * rows_, 0);
    for (int y = 0; y < rows_; ++y)
      for (int x = 0; x < cols_; ++x)
        if (sim.geometry().is_free(centre(x, y), 0)) at(x, y) = 1;
  }
  /// Runs the simulation until `time` s, marking what the cameras see.
  void run_until(salsa::Simulation& sim, double time) {
    while (sim.time() < time - 1e-9) {
      sim.run_steps(6);
      for (Vec2 p : sim.drone_positions()) {
        const int x0 = std::max(0, cell(p.x - range_, b_.min.x)), x1 = std::min(cols_ - 1, cell(p.x + range_, b_.min.x));
        const int y0 = std::max(0, cell(p.y - range_, b_.min.y)), y1 = std::min(rows_ - 1, cell(p.y + range_, b_.min.y));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x)
            if (at(x, y) == 1 && salsa::distance(p, centre(x, y)) <= range_) at(x, y) = 2;
      }
    }
  }
  /// Covered fraction of the free cells whose centre lies in `r` (the whole map by default).
  double fraction(std::optional<salsa::Rect> r = {}) const {
    std::size_t free = 0, covered = 0;
    for (int y = 0; y < rows_; ++y)
      for (int x = 0; x < cols_; ++x)
        if (at(x, y) && (!r || r->contains(centre(x, y)))) ++free, covered += at(x, y) == 2;
    return free ? static_cast<double>(covered) / static_cast<double>(free) : 1.0;
  }

 private:
  static constexpr double kCell = 5;
  Vec2 centre(int x, int y) const { return {b_.min.x + (x + 0.5) * kCell, b_.min.y + (y + 0.5) * kCell}; }
  static int cell(double v, double min) { return static_cast<int>(std::floor((v - min) / kCell)); }
  char& at(int x, int y) { return state_[static_cast<std::size_t>(y) * cols_ + x]; }
  char at(int x, int y) const { return state_[static_cast<std::size_t>(y) * cols_ + x]; }

  salsa::Rect b_;
  double range_;
  int cols_ = 0, rows_ = 0;
  std::vector<char> state_;  // per cell: 0 blocked, 1 free, 2 free and seen
};

/// Records what prepare() is shown of the drones and the map, and steers nowhere.
class PrepareRecorder final : public salsa::Behavior {
 public:
  std::vector<salsa::DroneProperties> drones;  // one per prepare
  salsa::MapData map;
  void prepare(const salsa::WorldView& world) override {
    drones.push_back(world.drone());
    map = world.map();
  }
  Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};

}  // namespace

class TestBehaviors : public QObject {
  Q_OBJECT

  std::unique_ptr<salsa::PluginHost> host_;

  std::unique_ptr<salsa::Simulation> simulation(const QString& json) {
    const salsa::TestSpec test = salsa::parse_test(json.toStdString(), "test_behaviors", *host_);
    return std::make_unique<salsa::Simulation>(salsa::make_setup(test, *host_, 2));
  }

 private Q_SLOTS:
  void initTestCase() {
    host_ = builtin_host();
    QVERIFY(host_->failures().empty());
  }

  // docs/behaviors.md's table of each built-in behavior (its section "## ... (`name`)") lists exactly the
  // parameters the behavior declares, in order.
  void docs_list_each_behaviors_own_parameters() {
    const QStringList lines = QString::fromUtf8(read_file(QString::fromStdString((source_dir() / "docs/behaviors.md").string()))).split('\n');
    const QRegularExpression section(R"(^## .*\(`([a-z_]+)`\)$)"), row(R"(^\| `([a-z_]+)` \|)");
    std::map<std::string, std::vector<std::string>> documented;
    std::string current;
    for (const QString& line : lines) {
      if (line.startsWith("## ")) {
        const auto m = section.match(line);
        current = m.hasMatch() ? m.captured(1).toStdString() : "";
        if (!current.empty()) documented[current];
      } else if (const auto m = row.match(line); m.hasMatch() && !current.empty()) {
        documented[current].push_back(m.captured(1).toStdString());
      }
    }
    for (const char* name : {"flocking", "random_walk", "pheromone_avoidance", "dynamic_space_partitioning", "dynamic_space_partitioning_paper",
                             "abm_flocking"}) {
      QVERIFY2(documented.contains(name), name);
      std::vector<std::string> declared;
      for (const salsa::Parameter& p : host_->behavior(name).factory.parameters) declared.push_back(p.name);
      const auto join = [](const std::vector<std::string>& v) {
        std::string s;
        for (const auto& x : v) s += x + " ";
        return s;
      };
      QVERIFY2(documented[name] == declared, qPrintable(QString("%1: docs list %2, the behavior declares %3")
                                                            .arg(name, QString::fromStdString(join(documented[name])), QString::fromStdString(join(declared)))));
    }
  }


  // A behavior's prepare() sees the test's drone configuration and its map (here a map file with two
  // obstacles), before any drone decides; a live drone configuration change shows in the next step.
  void prepare_sees_the_drone_configuration_and_the_map() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("map.json"), R"({"bounds": {"min": [0, 0], "max": [200, 100]}, "spawn": [20, 50],
      "obstacles": [[[40, 40], [60, 40], [60, 60], [40, 60]], [[100, 10], [130, 10], [115, 30]]]})"));
    const QString json = R"({"behavior": "random_walk", "drones": 4, "map": "%1",
      "drone": {"base": "medium", "max_speed": 7, "camera_range": 33, "radius": 0.8}})";
    const salsa::TestSpec test = salsa::parse_test(json.arg(dir.filePath("map.json")).toStdString(), "t.json", *host_);
    salsa::SimulationSetup setup = salsa::make_setup(test, *host_, 1);
    auto recorder = std::make_shared<PrepareRecorder>();
    setup.groups[0].behavior = recorder;
    salsa::Simulation sim(setup);
    sim.step();
    QCOMPARE(recorder->drones.size(), std::size_t(1));
    const salsa::DroneProperties& d = recorder->drones[0];
    QCOMPARE(d.max_speed, 7.0);
    QCOMPARE(d.camera_range, 33.0);
    QCOMPARE(d.radius, 0.8);
    QCOMPARE(d.max_force, test.groups[0].drone.max_force);  // the rest from "medium"
    QCOMPARE(d.mass, test.groups[0].drone.mass);
    QCOMPARE(d.obstacle_range, test.groups[0].drone.obstacle_range);
    QCOMPARE(d.detection_range, test.groups[0].drone.detection_range);
    QCOMPARE(recorder->map.bounds, (salsa::Rect{{0, 0}, {200, 100}}));
    QCOMPARE(recorder->map.spawn, Vec2(20, 50));
    QCOMPARE(recorder->map.obstacles.size(), std::size_t(2));
    QCOMPARE(recorder->map.obstacles[0], (salsa::Polyline{{40, 40}, {60, 40}, {60, 60}, {40, 60}}));
    QCOMPARE(recorder->map.obstacles[1], (salsa::Polyline{{100, 10}, {130, 10}, {115, 30}}));

    salsa::DroneConfig slower = test.groups[0].drone;
    slower.max_speed = 5;
    sim.set_drone_config(slower);
    sim.step();
    QCOMPARE(recorder->drones.size(), std::size_t(2));
    QCOMPARE(recorder->drones[1].max_speed, 5.0);
  }

  // The flocking plugin's decision is Table I's weighted sum (docs/behaviors.md), computed by hand (see
  // test_sdk's steering_helpers for the terms): 1.6 alignment + 3 separation + 1 cohesion + 4 obstacles.
  void flocking_decision_is_the_table1_formula_data() {
    QTest::addColumn<double>("max_force");
    QTest::addColumn<double>("x");
    QTest::addColumn<double>("y");
    QTest::newRow("max force 0.3") << 0.3 << -0.713096151261362 << 0.8220374745343582;
    QTest::newRow("max force 100") << 100.0 << -25.87626032246688 << 27.687946136074757;
  }
  void flocking_decision_is_the_table1_formula() {
    QFETCH(double, max_force);
    QFETCH(double, x);
    QFETCH(double, y);
    const auto& entry = host_->behavior("flocking");
    auto flocking = salsa::PluginHost::create(entry, salsa::ParameterValues(entry.factory.parameters));
    QCOMPARE(flocking->param("separation_distance"), 250.0);  // table1's values are the defaults
    QCOMPARE(flocking->param("alignment_weight"), 1.6);
    QCOMPARE(flocking->param("cohesion_weight"), 1.0);
    QCOMPARE(flocking->param("separation_weight"), 3.0);
    QCOMPARE(flocking->param("obstacle_avoidance_weight"), 4.0);
    flocking->reset(3);
    salsa::Perception me;
    me.velocity = {1, 0};
    me.max_speed = 10;
    me.max_force = max_force;
    const std::vector<salsa::Neighbour> neighbours{{{3, 4}, {0, 2}, 5, 1}, {{-6, 8}, {2, 0}, 10, 2}};
    const std::vector<salsa::ObstacleHit> hits{{{10, 0}, 10}, {{0, -5}, 5}};
    me.neighbours = neighbours;
    me.obstacles = hits;
    salsa::Rng rng;
    const Vec2 a = flocking->decide(me, rng);
    QVERIFY2(std::abs(a.x - x) < 1e-12 && std::abs(a.y - y) < 1e-12,
             qPrintable(QString("got (%1, %2), expected (%3, %4)").arg(a.x, 0, 'g', 17).arg(a.y, 0, 'g', 17).arg(x).arg(y)));
  }

  // One whole step of one drone through the core, against Table I's formulas written out here from
  // its definition in docs/benchmarks.md (no SDK helper): each term clamped to max force, the weighted
  // sum applied as is (so the velocity may change by up to 9.6 × max force in one step), then only the
  // speed clamped.
  // Six drones spawn in a disc 20–45 m from the west wall, so drone 0 has neighbours and wall hits.
  void flocking_step_is_the_table1_update_data() {
    QTest::addColumn<int>("seed");
    for (int seed : {1, 2, 3, 4, 5, 6}) QTest::newRow(qPrintable(QString("seed %1").arg(seed))) << seed;
  }
  void flocking_step_is_the_table1_update() {
    QFETCH(int, seed);
    auto sim = simulation(QString(R"({"behavior": "flocking", "drones": 6, "map": {"name": "empty", "params": {"size": 2000}},
                                      "spawn": {"point": [32, 1000], "radius": 12}, "decision_lag": 0, "seed": %1})")
                              .arg(seed));
    const std::vector<Vec2> p(sim->drone_positions().begin(), sim->drone_positions().end());
    const std::vector<Vec2> v(sim->drone_velocities().begin(), sim->drone_velocities().end());
    const double max_speed = 10, max_force = 0.3, size = 2000;  // the "small" drone, the 2 km map
    auto unit = [](Vec2 a) { const double l = std::hypot(a.x, a.y); return l > 0 ? Vec2{a.x / l, a.y / l} : Vec2{}; };
    auto clamp = [](Vec2 a, double m) { const double l = std::hypot(a.x, a.y); return l > m ? Vec2{a.x * m / l, a.y * m / l} : a; };
    auto steer = [&](Vec2 direction) { return clamp(unit(direction) * max_speed - v[0], max_force); };

    // Alignment, cohesion and separation over the drones within 134 m (all of them: the disc is 24 m wide).
    Vec2 velocities, positions, away;
    int count = 0;
    for (std::size_t j = 1; j < p.size(); ++j) {
      const double d = std::hypot(p[j].x - p[0].x, p[j].y - p[0].y);
      if (d >= 134) continue;
      ++count, velocities += v[j], positions += p[j];
      if (d > 0 && d < 250) away += unit(p[0] - p[j]) / d;
    }
    QCOMPARE(count, 5);
    const Vec2 alignment = steer(velocities / count), cohesion = steer(positions / count - p[0]),
               separation = away.is_zero() ? Vec2{} : steer(away / count);
    // Obstacle avoidance: 8 rays of 50.2 m at 0°, 45°, ..., 315° against the four walls of the square.
    Vec2 hits;
    int hit_count = 0;
    for (int k = 0; k < 8; ++k) {
      const Vec2 u{std::cos(k * salsa::pi / 4), std::sin(k * salsa::pi / 4)};
      double t = std::numeric_limits<double>::infinity();
      if (u.x < -1e-9) t = std::min(t, p[0].x / -u.x);
      if (u.x > 1e-9) t = std::min(t, (size - p[0].x) / u.x);
      if (u.y < -1e-9) t = std::min(t, p[0].y / -u.y);
      if (u.y > 1e-9) t = std::min(t, (size - p[0].y) / u.y);
      if (t > 0 && t <= 50.2) hits += unit(p[0] - (p[0] + u * t)) / t, ++hit_count;
    }
    QVERIFY2(hit_count >= 1, "drone 0 must see the wall for this test to mean anything");
    const Vec2 avoidance = steer(hits / hit_count);
    const Vec2 a = 1.6 * alignment + 3.0 * separation + 1.0 * cohesion + 4.0 * avoidance;
    const Vec2 sum = v[0] + a;
    const double speed = std::min(std::hypot(sum.x, sum.y), max_speed);
    const Vec2 expected = unit(sum) * speed;

    sim->step();
    const Vec2 commanded = sim->commanded_velocities()[0];  // what act handed to the body
    qInfo("|a| = %.3f (%.1f × max force), speed %.3f -> %.3f m/s, %d wall hits", a.length(), a.length() / max_force,
          v[0].length(), speed, hit_count);
    QVERIFY2(a.length() > 2 * max_force, "the step must exceed max force for this test to tell the clamps apart");
    QVERIFY2(salsa::distance(commanded, expected) < 1e-9,
             qPrintable(QString("commanded (%1, %2), table1 gives (%3, %4)").arg(commanded.x, 0, 'g', 12).arg(commanded.y, 0, 'g', 12)
                            .arg(expected.x, 0, 'g', 12).arg(expected.y, 0, 'g', 12)));
  }

  // Table I's separation distance (250 m) exceeds the detection range (134 m): every neighbour repels,
  // the swarm only expands and never forms a flock. A flock needs a separation distance well inside
  // the detection range, as in examples/flocking-forest.json (60 m).
  void flocking_aligns_the_swarm_data() {
    QTest::addColumn<int>("seed");
    QTest::newRow("seed 3") << 3;
    QTest::newRow("seed 4") << 4;
    QTest::newRow("seed 5") << 5;
  }
  void flocking_aligns_the_swarm() {
    QFETCH(int, seed);
    auto sim = simulation(QString(R"({"behavior": {"name": "flocking", "params": {"separation_distance": 60}},
                                      "drones": 30, "map": {"name": "empty", "params": {"size": 2000}}, "seed": %1})")
                              .arg(seed));
    const double initial = polarisation(*sim);
    sim->run_steps(60 * 60);  // 60 s
    const double final = polarisation(*sim);
    qInfo("polarisation %.3f -> %.3f", initial, final);
    QVERIFY2(final > 0.8, qPrintable(QString::number(final)));
    QVERIFY2(final > initial + 0.3, qPrintable(QString("%1 -> %2").arg(initial).arg(final)));
  }

  void flocking_without_alignment_and_cohesion_does_not_align() {
    // The control: the same start with only separation and obstacle avoidance stays disordered, so
    // the alignment above comes from the behavior's alignment and cohesion, not from the physics.
    auto sim = simulation(R"({"behavior": {"name": "flocking", "params": {"separation_distance": 60,
                              "alignment_weight": 0, "cohesion_weight": 0}},
                              "drones": 30, "map": {"name": "empty", "params": {"size": 2000}}, "seed": 3})");
    sim->run_steps(60 * 60);
    const double final = polarisation(*sim);
    qInfo("polarisation without alignment and cohesion %.3f", final);
    QVERIFY2(final < 0.5, qPrintable(QString::number(final)));
  }

  void dynamic_space_partitioning_spreads_out() {
    const int drones = 20;
    const double size = 500;
    auto sim = simulation(QString(R"({"behavior": "dynamic_space_partitioning", "drones": %1,
                                      "map": {"name": "empty", "params": {"size": %2}},
                                      "spawn": {"radius": 15}, "seed": 5})")
                              .arg(drones)
                              .arg(size));
    const double spacing = std::sqrt(size * size / drones);  // the equilibrium spacing, about 112 m
    std::vector<double> nn{mean_nearest_neighbour(*sim)};
    for (int k = 0; k < 4; ++k) {
      sim->run_steps(15 * 60);  // 15 s
      nn.push_back(mean_nearest_neighbour(*sim));
    }
    qInfo("mean nearest-neighbour distance %.1f %.1f %.1f %.1f %.1f m (equilibrium spacing %.1f m)", nn[0], nn[1], nn[2],
          nn[3], nn[4], spacing);
    QVERIFY2(nn[0] < 0.2 * spacing, "the start must be tight for this test to mean anything");
    QVERIFY2(nn[1] > nn[0] && nn[2] > nn[1], "the spacing must grow while the swarm spreads");
    QVERIFY2(nn.back() > 0.5 * spacing, qPrintable(QString::number(nn.back())));
    // Spread over the whole area: a drone in each quadrant.
    std::set<int> quadrants;
    for (Vec2 p : sim->drone_positions()) quadrants.insert((p.x > size / 2) + 2 * (p.y > size / 2));
    QCOMPARE(quadrants.size(), std::size_t(4));
  }

  // Each drone sweeps the region it was given, and the regions tile the free map: 30 drones on the
  // 2 km map (the forest-health map) cover nearly all of it, every 500 m block included, empty or forest
  // (the default forest at 2 km: 192 clusters). Measured 91.0 % / 99.1 % at 600 / 900 s on the empty map,
  // 80–87 % / 90–97 % in the forest (seeds 1–3); a disc around each point reached 42 % / 48 % and 24–33 %.
  void dynamic_space_partitioning_covers_the_free_map_data() {
    QTest::addColumn<QString>("map");
    QTest::addColumn<double>("at_600_s");
    QTest::addColumn<double>("at_900_s");
    QTest::addColumn<double>("every_block");
    QTest::newRow("empty 2 km") << R"({"name": "empty", "params": {"size": 2000}})" << 0.85 << 0.97 << 0.9;
    QTest::newRow("forest 2 km") << R"({"name": "forest", "params": {"size": 2000}})" << 0.72 << 0.85 << 0.6;
  }
  void dynamic_space_partitioning_covers_the_free_map() {
    QFETCH(QString, map);
    QFETCH(double, at_600_s);
    QFETCH(double, at_900_s);
    QFETCH(double, every_block);
    auto sim = simulation(QString(R"({"behavior": "dynamic_space_partitioning", "drones": 30, "map": %1, "seed": 1})").arg(map));
    Coverage coverage(*sim);
    coverage.run_until(*sim, 600);
    const double early = coverage.fraction();
    coverage.run_until(*sim, 900);
    const double late = coverage.fraction();
    double worst = 1;
    for (double x = 0; x < 2000; x += 500)
      for (double y = 0; y < 2000; y += 500) worst = std::min(worst, coverage.fraction(salsa::Rect{{x, y}, {x + 500, y + 500}}));
    qInfo("coverage %.1f %% at 600 s, %.1f %% at 900 s; least covered 500 m block %.1f %%", 100 * early, 100 * late, 100 * worst);
    QVERIFY2(early >= at_600_s, qPrintable(QString::number(early)));
    QVERIFY2(late >= at_900_s, qPrintable(QString::number(late)));
    QVERIFY2(worst >= every_block, qPrintable(QString::number(worst)));
  }

  void pheromone_avoidance_covers_more_than_random_walk_data() {
    QTest::addColumn<QString>("map");
    QTest::addColumn<int>("seed");
    QTest::newRow("forest, seed 1") << "forest" << 1;
    QTest::newRow("forest, seed 2") << "forest" << 2;
    QTest::newRow("empty, seed 1") << "empty" << 1;
  }
  void pheromone_avoidance_covers_more_than_random_walk() {
    QFETCH(QString, map);
    QFETCH(int, seed);
    auto coverage = [&](const char* behavior) {
      auto sim = simulation(QString(R"({"behavior": "%1", "drones": 10, "map": {"name": "%3", "params": {"size": 400}},
                                        "seed": %2})")
                                .arg(behavior)
                                .arg(seed)
                                .arg(map));
      std::unordered_set<long long> cells;  // 10 m cells visited by any drone, sampled every step
      for (int step = 0; step < 150 * 60; ++step) {
        sim->step();
        for (Vec2 p : sim->drone_positions())
          cells.insert(static_cast<long long>(std::floor(p.x / 10)) * 100000 + static_cast<long long>(std::floor(p.y / 10)));
      }
      return cells.size();
    };
    const std::size_t pheromone = coverage("pheromone_avoidance"), random = coverage("random_walk");
    qInfo("cells visited in 150 s: pheromone_avoidance %zu, random_walk %zu (of 1600)", pheromone, random);
    QVERIFY2(static_cast<double>(pheromone) > 1.1 * static_cast<double>(random),
             qPrintable(QString("%1 vs %2").arg(pheromone).arg(random)));
  }

  // The forest's default obstacle count scales with the area: the same obstacles per km² at every size
  // (12 clusters on 500 m as always, 192 on 2 km), and an explicit cluster count is used as given.
  void forest_obstacles_scale_with_area_data() {
    QTest::addColumn<double>("size");
    QTest::addColumn<int>("clusters");  // 0: the default
    QTest::addColumn<double>("per_km2_low");
    QTest::addColumn<double>("per_km2_high");
    QTest::newRow("500 m") << 500.0 << 0 << 150.0 << 200.0;
    QTest::newRow("1 km") << 1000.0 << 0 << 150.0 << 200.0;
    QTest::newRow("2 km") << 2000.0 << 0 << 150.0 << 200.0;
    QTest::newRow("4 km") << 4000.0 << 0 << 150.0 << 200.0;
    QTest::newRow("2 km, 12 clusters given") << 2000.0 << 12 << 0.0 << 12.0;  // at most 48 obstacles
  }
  void forest_obstacles_scale_with_area() {
    QFETCH(double, size);
    QFETCH(int, clusters);
    QFETCH(double, per_km2_low);
    QFETCH(double, per_km2_high);
    const auto& entry = host_->map("forest");
    salsa::ParameterValues params(entry.factory.parameters);
    params.set("size", size);
    if (clusters) params.set("clusters", clusters);
    const auto forest = salsa::PluginHost::create(entry, params);
    salsa::Rng rng(4);
    const salsa::MapData map = forest->generate("", rng);
    const double per_km2 = static_cast<double>(map.obstacles.size()) / (size * size / 1e6);
    qInfo("%.0f m: %zu obstacles, %.1f per km²", size, map.obstacles.size(), per_km2);
    QVERIFY2(per_km2 >= per_km2_low && per_km2 <= per_km2_high, qPrintable(QString::number(per_km2)));
  }

  // Every step, every drone: inside the bounds and outside every obstacle polygon. "blind" switches
  // the behavior's obstacle avoidance off, so drones fly into obstacles and walls all the time and the
  // physics alone must keep them out.
  void random_walk_stays_in_bounds_and_out_of_obstacles_data() {
    QTest::addColumn<QString>("params");
    QTest::addColumn<double>("near");  // m: drones must come this close to walls or obstacles
    QTest::newRow("default") << "{}" << 10.0;
    QTest::newRow("blind") << R"({"obstacle_avoidance_weight": 0, "turn_distance": 0})" << 1.2;
  }
  void random_walk_stays_in_bounds_and_out_of_obstacles() {
    QFETCH(QString, params);
    QFETCH(double, near);
    auto sim = simulation(QString(R"({"behavior": {"name": "random_walk", "params": %1}, "drones": 30,
                                      "map": {"name": "forest", "params": {"size": 300, "clusters": 20}}, "seed": 11})")
                              .arg(params));
    const salsa::MapData& map = sim->map();
    QVERIFY2(map.obstacles.size() >= 20, "the forest must have obstacles for this test to mean anything");
    const salsa::Rect b = map.bounds;
    const double r = sim->drone_config().radius;
    std::size_t close = 0;
    for (int step = 0; step < 60 * 60; ++step) {
      sim->step();
      const auto positions = sim->drone_positions();
      for (std::size_t i = 0; i < positions.size(); ++i) {
        const Vec2 p = positions[i];
        // The body keeps (almost) its radius from the walls: Box2D allows a little overlap.
        if (!(p.x > b.min.x + 0.8 * r && p.x < b.max.x - 0.8 * r && p.y > b.min.y + 0.8 * r && p.y < b.max.y - 0.8 * r))
          QFAIL(qPrintable(QString("drone %1 left the map at t = %2 s: (%3, %4)").arg(i).arg(sim->time()).arg(p.x).arg(p.y)));
        for (std::size_t k = 0; k < map.obstacles.size(); ++k)
          if (salsa::inside_polygon(p, map.obstacles[k]))
            QFAIL(qPrintable(QString("drone %1 inside obstacle %2 at t = %3 s").arg(i).arg(k).arg(sim->time())));
        if (!sim->geometry().is_free(p, near)) ++close;
      }
    }
    qInfo("drone-steps within %.1f m of a wall or obstacle: %zu", near, close);
    QVERIFY2(close > 0, "the drones never came near an obstacle: the test would prove nothing");
  }
};

QTEST_GUILESS_MAIN(TestBehaviors)
#include "test_behaviors.moc"
