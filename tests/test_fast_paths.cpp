// The optimised paths give exactly what the straightforward definitions give: neighbour sets (grid)
// and target detection (target grid) against all pairs, obstacle rays and free-space tests (segment
// grid) against all segments, nearest-neighbour distances, and parallel decide against serial.
#include <QtTest>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>

#include "common.hpp"
#include "salsa/core/model/map_check.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/model/static_geometry.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa_test;
using salsa::Vec2;

Q_DECLARE_METATYPE(Vec2)

namespace {

/// Records what each drone perceives. decide() may run on several threads at once: it writes only
/// the slot of the drone it decides for.
class Recorder final : public salsa::Behavior {
 public:
  struct Seen {
    Vec2 position, velocity;
    std::vector<salsa::Neighbour> neighbours;
    std::vector<salsa::ObstacleHit> obstacles;
    std::vector<salsa::TargetSeen> targets;
    int decisions = 0;
  };
  std::vector<Seen> seen;
  Vec2 steering;  // what every drone returns
  bool wander = false;  // instead: full force, each drone turning its own way over time
  salsa::Senses senses_declared;  // what it tells the core it reads

  void reset(std::size_t drones) override { seen.assign(drones, {}); }
  salsa::Senses senses() const override { return senses_declared; }
  Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    Seen& s = seen[me.id];
    s.position = me.position;
    s.velocity = me.velocity;
    s.neighbours.assign(me.neighbours.begin(), me.neighbours.end());
    s.obstacles.assign(me.obstacles.begin(), me.obstacles.end());
    s.targets.assign(me.targets.begin(), me.targets.end());
    ++s.decisions;
    return wander ? Vec2::polar(me.max_force, 0.9 * me.id + 0.5 * me.time) : steering;
  }
};

/// Logs the sightings it is handed, step by step, as (drone, target) pairs in the order they came.
class SightingLog final : public salsa::ContactHandler {
 public:
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  explicit SightingLog(salsa::Sightings wants, double dt) : wants_(wants), dt_(dt) {}
  std::map<std::int64_t, std::vector<Pair>> by_step;
  salsa::Sightings sightings() const override { return wants_; }
  void on_contact(const salsa::ContactEvent& e, salsa::ContactActions&) override {
    if (e.kind == salsa::ContactKind::target_in_view) by_step[std::llround(e.time / dt_)].push_back({e.drone, e.other});
  }

 private:
  salsa::Sightings wants_;
  double dt_;
};

/// A target kind whose camera sees twice as far as the drones' camera range; with `widened`, it says
/// so through view_range, without it the core's default query distance (camera range + radius) cuts
/// its view short.
class FarSight final : public salsa::TargetKind {
 public:
  explicit FarSight(bool widened, double range_factor = 2) : widened_(widened), factor_(range_factor) {}
  double radius() const override { return 0.5; }
  bool in_view(double distance, double camera_range) const override { return distance < 2 * camera_range; }
  double view_range(double camera_range) const override {
    return widened_ ? factor_ * camera_range : TargetKind::view_range(camera_range);
  }

 private:
  bool widened_;
  double factor_;
};

/// Circles the spawn point: a behavior whose result depends on every drone's neighbours and its RNG,
/// for the parallel-vs-serial comparison.
class Jitter final : public salsa::Behavior {
 public:
  Vec2 decide(const salsa::Perception& me, salsa::Rng& rng) override {
    Vec2 away;
    for (const auto& n : me.neighbours) away += (me.position - n.position) / (n.distance * n.distance + 1);
    return away * 5 + Vec2::polar(0.2, rng.angle()) + salsa::avoid_obstacles(me);
  }
};

/// A polygon around `centre`, its points kept inside `bounds` (the core refuses points outside).
salsa::Polyline random_polygon(salsa::Rng& rng, Vec2 centre, double radius, const salsa::Rect& bounds) {
  const int n = 3 + static_cast<int>(rng.index(6));
  salsa::Polyline p;
  const double phase = rng.angle();
  for (int k = 0; k < n; ++k) {
    const Vec2 v = centre + Vec2::polar(radius * rng.uniform(0.5, 1), phase + 2 * salsa::pi * k / n);
    p.push_back({std::clamp(v.x, bounds.min.x, bounds.max.x), std::clamp(v.y, bounds.min.y, bounds.max.y)});
  }
  return p;
}

/// A map of `size` m with random solid polygons, hollow outlines, open lines and axis-aligned boxes
/// whose corners sit on whole metres (rays and points hit them exactly).
salsa::MapData random_map(std::uint64_t seed, double size, int shapes) {
  salsa::Rng rng(seed, 0);
  salsa::MapData map;
  map.bounds = {{0, 0}, {size, size}};
  map.spawn = map.bounds.centre();
  const salsa::Rect inner{{size * 0.05, size * 0.05}, {size * 0.95, size * 0.95}};
  for (int i = 0; i < shapes; ++i) {
    const Vec2 c = rng.in_rect(inner);
    switch (i % 4) {
      case 0: map.obstacles.push_back(random_polygon(rng, c, rng.uniform(1, size / 20), map.bounds)); break;
      case 1: map.hollow.push_back(random_polygon(rng, c, rng.uniform(1, size / 10), map.bounds)); break;
      case 2: {
        salsa::Polyline line{c};
        for (int k = 0; k < 3; ++k) line.push_back(line.back() + Vec2::polar(rng.uniform(0.1, size / 8), rng.angle()));
        for (Vec2& p : line) p = {std::clamp(p.x, 0.0, size), std::clamp(p.y, 0.0, size)};
        map.lines.push_back(line);
        break;
      }
      default: {
        const double x = std::floor(c.x), y = std::floor(c.y), w = 1 + static_cast<double>(rng.index(20));
        map.obstacles.push_back({{x, y}, {x + w, y}, {x + w, y + w}, {x, y + w}});
        break;
      }
    }
  }
  // A spawn point in free space, or the simulation refuses the map.
  const salsa::StaticGeometry g(map, 50);
  while (!g.is_free(map.spawn, 2)) map.spawn = rng.in_rect(inner);
  return map;
}

/// The straightforward ray cast: every segment of the map.
std::optional<salsa::ObstacleHit> brute_ray(const salsa::StaticGeometry& g, Vec2 from, Vec2 dir, double range) {
  std::optional<double> best;
  for (const salsa::Segment& s : g.segments())
    if (auto t = salsa::ray_segment(from, dir, range, s); t && (!best || *t < *best)) best = t;
  if (!best) return std::nullopt;
  return salsa::ObstacleHit{from + dir * *best, *best};
}

bool same_hit(const std::optional<salsa::ObstacleHit>& a, const std::optional<salsa::ObstacleHit>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a || (a->point == b->point && a->distance == b->distance);
}

QString show(const std::optional<salsa::ObstacleHit>& h) {
  return h ? QString("hit at %1 m (%2, %3)").arg(h->distance, 0, 'g', 17).arg(h->point.x, 0, 'g', 17).arg(h->point.y, 0, 'g', 17)
           : QString("no hit");
}

}  // namespace

class TestFastPaths : public QObject {
  Q_OBJECT

  std::unique_ptr<salsa::PluginHost> host_;

  std::shared_ptr<salsa::TargetKind> trees() {
    const auto& e = host_->target_kind("tree");
    return salsa::PluginHost::create(e, salsa::ParameterValues(e.factory.parameters));
  }
  std::shared_ptr<salsa::ContactHandler> detect_targets() {
    const auto& e = host_->contact_handler("detect_targets");
    return salsa::PluginHost::create(e, salsa::ParameterValues(e.factory.parameters));
  }

 private Q_SLOTS:
  void initTestCase() {
    host_ = builtin_host();
    QVERIFY(host_->failures().empty());
  }

  // ---------------------------------------------------------------- perception in the simulation
  void perception_matches_brute_force_data() {
    QTest::addColumn<int>("drones");
    QTest::addColumn<double>("size");
    QTest::addColumn<double>("detection");
    QTest::addColumn<int>("shapes");
    QTest::addColumn<int>("threads");
    QTest::addColumn<int>("lag");
    QTest::newRow("dense, paper ranges") << 300 << 400.0 << 134.0 << 40 << 2 << 1;
    QTest::newRow("dense, no decision lag") << 300 << 400.0 << 134.0 << 40 << 2 << 0;
    QTest::newRow("sparse, short range") << 200 << 2000.0 << 30.0 << 80 << 2 << 1;
    QTest::newRow("range beyond the map") << 60 << 200.0 << 1000.0 << 20 << 1 << 1;
    QTest::newRow("tiny range") << 400 << 300.0 << 2.5 << 30 << 2 << 0;
    QTest::newRow("one drone") << 1 << 300.0 << 134.0 << 10 << 1 << 1;
    QTest::newRow("two drones") << 2 << 50.0 << 134.0 << 0 << 1 << 0;
  }
  void perception_matches_brute_force() {
    QFETCH(int, drones);
    QFETCH(double, size);
    QFETCH(double, detection);
    QFETCH(int, shapes);
    QFETCH(int, threads);
    QFETCH(int, lag);
    auto recorder = std::make_shared<Recorder>();
    recorder->steering = {0.05, -0.03};
    salsa::SimulationSetup setup;
    setup.map = random_map(static_cast<std::uint64_t>(drones + shapes), size, shapes);
    setup.groups[0].spawn_mode = salsa::SpawnMode::uniform;
    setup.groups[0].drone.detection_range = detection;
    setup.groups[0].drone.obstacle_rays = 16;
    setup.groups[0].drones = static_cast<std::size_t>(drones);
    setup.groups[0].behavior = recorder;
    setup.target_kind = trees();
    setup.targets = 500;
    setup.contact_handlers = {detect_targets()};
    setup.seed = 17;
    setup.threads = threads;
    setup.decision_lag = lag;
    salsa::Simulation sim(setup);
    const salsa::DroneConfig& cfg = sim.drone_config();
    const double reach = cfg.camera_range + setup.target_kind->radius();
    const std::size_t n = sim.drone_count();
    QCOMPARE(n, std::size_t(drones));

    // Brute-force observation counts: each step counts the targets in view of the positions the drones
    // sensed from (those at the start of the step), and a target is found when that step ends.
    std::vector<std::uint64_t> observations(sim.targets().size(), 0);
    std::vector<double> first_seen(sim.targets().size(), -1);
    std::vector<std::int64_t> first_by(sim.targets().size(), -1);
    auto count_views = [&] {
      const auto pos = sim.drone_positions();
      for (std::size_t i = 0; i < n; ++i)  // by drone: the lowest id among the first to see it finds it
        for (std::size_t t = 0; t < sim.targets().size(); ++t)
          if (salsa::distance(pos[i], sim.targets()[t].position) < reach) {
            ++observations[t];
            if (first_by[t] < 0) first_seen[t] = sim.time() + sim.dt(), first_by[t] = static_cast<std::int64_t>(i);
          }
    };

    std::size_t neighbour_pairs = 0, hits = 0, seen_targets = 0;
    for (int step = 0; step < 20; ++step) {
      const std::vector<Vec2> pos(sim.drone_positions().begin(), sim.drone_positions().end());
      const std::vector<Vec2> vel(sim.drone_velocities().begin(), sim.drone_velocities().end());
      count_views();
      sim.step();
      for (std::size_t i = 0; i < n; ++i) {
        const Recorder::Seen& s = recorder->seen[i];
        QCOMPARE(s.decisions, step + 1);
        QCOMPARE(s.position, pos[i]);
        QCOMPARE(s.velocity, vel[i]);

        // Neighbours: every other drone closer than the detection range.
        std::vector<std::uint32_t> expected, got;
        for (std::size_t j = 0; j < n; ++j)
          if (j != i && salsa::distance(pos[i], pos[j]) < detection) expected.push_back(static_cast<std::uint32_t>(j));
        for (const auto& nb : s.neighbours) {
          got.push_back(nb.id);
          QCOMPARE(nb.position, pos[nb.id]);
          QCOMPARE(nb.velocity, vel[nb.id]);
          QVERIFY(std::abs(nb.distance - salsa::distance(pos[i], pos[nb.id])) < 1e-9);
        }
        std::sort(got.begin(), got.end());
        QVERIFY2(got == expected, qPrintable(QString("step %1, drone %2: %3 neighbours, brute force %4")
                                                 .arg(step).arg(i).arg(got.size()).arg(expected.size())));
        neighbour_pairs += got.size();

        // Obstacle rays: the nearest hit over all segments, ray by ray, misses left out.
        std::vector<salsa::ObstacleHit> rays;
        for (int k = 0; k < cfg.obstacle_rays; ++k)
          if (auto h = brute_ray(sim.geometry(), pos[i], Vec2::polar(1, 2 * salsa::pi * k / cfg.obstacle_rays), cfg.obstacle_range))
            rays.push_back(*h);
        QCOMPARE(s.obstacles.size(), rays.size());
        for (std::size_t k = 0; k < rays.size(); ++k) {
          QCOMPARE(s.obstacles[k].point, rays[k].point);
          QCOMPARE(s.obstacles[k].distance, rays[k].distance);
        }
        hits += rays.size();

        // Targets in view: centre distance below camera range + tree radius.
        std::vector<std::uint32_t> in_view, perceived;
        for (std::size_t t = 0; t < sim.targets().size(); ++t)
          if (salsa::distance(pos[i], sim.targets()[t].position) < reach) in_view.push_back(static_cast<std::uint32_t>(t));
        for (const auto& t : s.targets) {
          perceived.push_back(t.id);
          QCOMPARE(t.position, sim.targets()[t.id].position);
          QVERIFY(std::abs(t.distance - salsa::distance(pos[i], t.position)) < 1e-9);
        }
        std::sort(perceived.begin(), perceived.end());
        QVERIFY2(perceived == in_view, qPrintable(QString("step %1, drone %2: %3 targets in view, brute force %4")
                                                      .arg(step).arg(i).arg(perceived.size()).arg(in_view.size())));
        seen_targets += perceived.size();
      }
    }
    // Targets: observations, found, found by whom and when, as the brute force saw them.
    std::size_t found = 0;
    for (std::size_t t = 0; t < sim.targets().size(); ++t) {
      const salsa::TargetState& ts = sim.targets()[t];
      QCOMPARE(ts.observations, observations[t]);
      QCOMPARE(ts.found(), first_by[t] >= 0);
      if (ts.found()) {
        QCOMPARE(ts.found_by, first_by[t]);  // the lowest drone id among the first to see it
        QCOMPARE(ts.found_time, first_seen[t]);
        ++found;
      }
    }
    QCOMPARE(sim.targets_found(), found);
    qInfo("checked %zu neighbour pairs, %zu ray hits, %zu targets in view, %zu targets found", neighbour_pairs, hits,
          seen_targets, found);
    if (drones > 2) QVERIFY(neighbour_pairs > 0 && hits > 0 && seen_targets > 0);
  }

  // A target kind's view_range is how far the detect phase looks: an in_view of 2 × camera range
  // with a matching view_range sees every target within that (as the brute force does), one without
  // it only those within camera range + radius.
  void view_range_sets_how_far_targets_are_seen_data() {
    QTest::addColumn<bool>("widened");
    QTest::addColumn<int>("lag");
    QTest::newRow("view_range 2 × camera range") << true << 1;
    QTest::newRow("view_range 2 × camera range, no lag") << true << 0;
    QTest::newRow("default view_range") << false << 1;
  }
  void view_range_sets_how_far_targets_are_seen() {
    QFETCH(bool, widened);
    QFETCH(int, lag);
    auto recorder = std::make_shared<Recorder>();
    recorder->steering = {0.05, -0.03};
    salsa::SimulationSetup setup;
    setup.map = random_map(7, 500, 20);
    setup.groups[0].spawn_mode = salsa::SpawnMode::uniform;
    setup.groups[0].drone.camera_range = 20;
    setup.groups[0].drones = 150;
    setup.groups[0].behavior = recorder;
    setup.target_kind = std::make_shared<FarSight>(widened);
    setup.targets = 600;
    setup.contact_handlers = {detect_targets()};
    setup.seed = 11;
    setup.threads = 2;
    setup.decision_lag = lag;
    salsa::Simulation sim(setup);
    const double camera = sim.drone_config().camera_range;
    const double reach = widened ? 2 * camera : camera + 0.5;
    std::size_t seen = 0, beyond_camera = 0;
    for (int step = 0; step < 10; ++step) {
      const std::vector<Vec2> pos(sim.drone_positions().begin(), sim.drone_positions().end());
      sim.step();
      for (std::size_t i = 0; i < sim.drone_count(); ++i) {
        std::vector<std::uint32_t> expected, perceived;
        for (std::size_t t = 0; t < sim.targets().size(); ++t)
          if (salsa::distance(pos[i], sim.targets()[t].position) < reach) expected.push_back(static_cast<std::uint32_t>(t));
        for (const auto& t : recorder->seen[i].targets) {
          perceived.push_back(t.id);
          if (t.distance >= camera + 0.5) ++beyond_camera;
        }
        std::sort(perceived.begin(), perceived.end());
        QVERIFY2(perceived == expected, qPrintable(QString("step %1, drone %2: %3 targets in view, brute force %4")
                                                       .arg(step).arg(i).arg(perceived.size()).arg(expected.size())));
        seen += perceived.size();
      }
    }
    QVERIFY2(seen > 100, qPrintable(QString("only %1 sightings: the test shows little").arg(seen)));
    if (widened) QVERIFY2(beyond_camera > 50, qPrintable(QString("%1 sightings beyond camera range").arg(beyond_camera)));
    else QCOMPARE(beyond_camera, std::size_t(0));
  }

  // A view_range that is not a finite distance >= 0 is the plugin's bad data: refused, naming it.
  void bad_view_range_is_refused_data() {
    QTest::addColumn<double>("factor");
    QTest::newRow("negative") << -1.0;
    QTest::newRow("NaN") << std::nan("");
    QTest::newRow("infinite") << std::numeric_limits<double>::infinity();
  }
  void bad_view_range_is_refused() {
    QFETCH(double, factor);
    salsa::SimulationSetup setup;
    setup.map = random_map(3, 200, 0);
    setup.groups[0].behavior = std::make_shared<Recorder>();
    setup.target_kind = std::make_shared<FarSight>(true, factor);
    setup.targets = 10;
    try {
      salsa::Simulation sim(setup);
      QFAIL("a bad view_range was accepted");
    } catch (const std::invalid_argument& e) {
      QVERIFY2(QString(e.what()).startsWith("view_range: ") && QString(e.what()).contains("allowed: a finite distance"), e.what());
    }
  }

  void senses_limit_perception_data() {
    QTest::addColumn<bool>("neighbours");
    QTest::addColumn<bool>("targets");
    QTest::newRow("everything") << true << true;
    QTest::newRow("neighbours only") << true << false;
    QTest::newRow("targets only") << false << true;
    QTest::newRow("obstacles only") << false << false;
  }
  /// A behavior gets only what it declared it senses, every drone its own state and obstacle hits; and
  /// the core's own detection (observations, who found what and when) does not depend on it.
  void senses_limit_perception() {
    QFETCH(bool, neighbours);
    QFETCH(bool, targets);
    auto run = [this](salsa::Senses senses) {
      auto recorder = std::make_shared<Recorder>();
      recorder->senses_declared = senses;
      salsa::SimulationSetup setup;
      setup.map = random_map(5, 300, 6);
      setup.groups[0].drones = 30;
      setup.groups[0].behavior = recorder;
      setup.target_kind = trees();
      setup.targets = 2000;
      setup.contact_handlers = {detect_targets()};
      setup.seed = 3;
      auto sim = std::make_unique<salsa::Simulation>(setup);
      for (int step = 0; step < 10; ++step) sim->step();
      return std::pair(recorder, std::move(sim));
    };
    const auto [all, all_sim] = run({});
    const auto [some, some_sim] = run({.neighbours = neighbours, .targets = targets});
    std::size_t neighbour_lists = 0, target_lists = 0;
    for (std::size_t i = 0; i < all->seen.size(); ++i) {
      const Recorder::Seen &a = all->seen[i], &b = some->seen[i];
      QCOMPARE(b.position, a.position);
      QCOMPARE(b.obstacles.size(), a.obstacles.size());
      QCOMPARE(b.neighbours.size(), neighbours ? a.neighbours.size() : 0);
      QCOMPARE(b.targets.size(), targets ? a.targets.size() : 0);
      neighbour_lists += !a.neighbours.empty();
      target_lists += !a.targets.empty();
    }
    QVERIFY(neighbour_lists > 0 && target_lists > 0);  // there was something to leave out
    for (std::size_t t = 0; t < all_sim->targets().size(); ++t) {
      QCOMPARE(some_sim->targets()[t].observations, all_sim->targets()[t].observations);
      QCOMPARE(some_sim->targets()[t].found_by, all_sim->targets()[t].found_by);
      QCOMPARE(some_sim->targets()[t].found_time, all_sim->targets()[t].found_time);
    }
  }

  /// Sightings::on_entry hands a handler exactly the sightings of the every-step stream that were not
  /// in it the step before (a noisy camera's miss included), in the same order; after targets are
  /// re-made, everything in view comes anew. Alone or beside an every-step handler, the same events.
  // Sense answers from a list per drone kept across steps: over a long flight at full speed (each
  // list remade many times) and a camera change in mid-flight (the target grid remade with another
  // cell size), every drone's targets are exactly the target grid's query, in the grid's order (the
  // order a behavior sums them in and miss draws are made in).
  void targets_in_view_are_the_grids_answer_in_its_order() {
    auto recorder = std::make_shared<Recorder>();
    recorder->wander = true;
    salsa::SimulationSetup setup;
    setup.map = random_map(9, 400, 8);
    setup.groups[0].spawn_mode = salsa::SpawnMode::uniform;
    setup.groups[0].drones = 40;
    setup.groups[0].behavior = recorder;
    setup.target_kind = trees();
    setup.targets = 3000;
    setup.seed = 5;
    setup.threads = 2;
    salsa::Simulation sim(setup);
    std::vector<Vec2> targets;
    for (const salsa::TargetState& t : sim.targets()) targets.push_back(t.position);
    std::size_t checked = 0;
    double flown = 0;
    for (int step = 0; step < 600; ++step) {
      if (step == 300) {
        salsa::DroneConfig cfg = sim.drone_config();
        cfg.camera_range = 25;
        sim.set_drone_config(cfg);
      }
      const double reach = sim.drone_config().camera_range + setup.target_kind->radius();
      salsa::PointGrid grid;
      grid.build(targets, std::max(reach, 1.0));  // as the core builds its target grid
      const std::vector<Vec2> pos(sim.drone_positions().begin(), sim.drone_positions().end());
      sim.step();
      for (std::uint32_t i = 0; i < pos.size(); ++i) {
        std::vector<std::uint32_t> expected, got;
        grid.query(pos[i], reach, [&](std::uint32_t t, Vec2, double) { expected.push_back(t); });
        for (const salsa::TargetSeen& t : recorder->seen[i].targets) got.push_back(t.id);
        QVERIFY2(got == expected, qPrintable(QString("step %1, drone %2: %3 targets, the grid's query %4")
                                                 .arg(step).arg(i).arg(got.size()).arg(expected.size())));
        checked += got.size();
      }
      flown += salsa::distance(pos[0], sim.drone_positions()[0]);
    }
    qInfo("%zu targets in view checked; drone 0 flew %.0f m", checked, flown);
    QVERIFY(checked > 5000);
    QVERIFY(flown > 50);  // past its list's margin (5 m, then 7.5 m) many times
  }

  void sightings_on_entry_are_the_first_of_each_stay() {
    auto run = [this](bool with_every_step) {
      auto recorder = std::make_shared<Recorder>();
      recorder->steering = {0.05, -0.03};
      salsa::SimulationSetup setup;
      setup.map = random_map(5, 300, 6);
      setup.groups[0].drones = 30;
      setup.groups[0].drone.miss_probability = 0.2;
      setup.groups[0].behavior = recorder;
      setup.target_kind = trees();
      setup.targets = 2000;
      setup.seed = 3;
      auto every = std::make_shared<SightingLog>(salsa::Sightings::every_step, setup.dt);
      auto entry = std::make_shared<SightingLog>(salsa::Sightings::on_entry, setup.dt);
      setup.contact_handlers = {entry, detect_targets()};
      if (with_every_step) setup.contact_handlers.push_back(every);
      salsa::Simulation sim(setup);
      for (int step = 0; step < 60; ++step) {
        if (step == 30) sim.set_targets(trees(), 2000);  // the same trees, re-made
        sim.step();
      }
      return std::pair(every, entry);
    };
    const auto [every, entry] = run(true);
    std::size_t all = 0, entries = 0;
    std::vector<SightingLog::Pair> before;
    for (std::int64_t step = 1; step <= 60; ++step) {
      const std::vector<SightingLog::Pair>& now = every->by_step[step];
      std::vector<SightingLog::Pair> expected;
      for (const auto& pair : now)
        if (step == 31 || std::find(before.begin(), before.end(), pair) == before.end()) expected.push_back(pair);
      QVERIFY2(entry->by_step[step] == expected, qPrintable(QString("step %1: %2 entries, expected %3")
                                                               .arg(step).arg(entry->by_step[step].size()).arg(expected.size())));
      all += now.size(), entries += expected.size();
      before = now;
    }
    qInfo("%zu sightings, %zu of them entries", all, entries);
    QVERIFY(entries > 0 && entries * 4 < all);  // most sightings repeat the step before's
    QCOMPARE(run(false).second->by_step, entry->by_step);
  }

  void nearest_neighbour_distances_match_brute_force_data() {
    QTest::addColumn<int>("drones");
    QTest::addColumn<double>("detection");
    QTest::newRow("neighbours in range") << 200 << 134.0;
    QTest::newRow("most beyond range") << 50 << 3.0;  // the query has to widen
    QTest::newRow("single drone") << 1 << 134.0;
  }
  void nearest_neighbour_distances_match_brute_force() {
    QFETCH(int, drones);
    QFETCH(double, detection);
    salsa::SimulationSetup setup;
    setup.map = random_map(3, 3000, 10);
    setup.groups[0].spawn_mode = salsa::SpawnMode::uniform;
    setup.groups[0].drone.detection_range = detection;
    setup.groups[0].drones = static_cast<std::size_t>(drones);
    setup.groups[0].behavior = std::make_shared<Recorder>();
    salsa::Simulation sim(setup);
    sim.run_steps(3);
    const auto got = sim.nearest_neighbour_distances();
    const auto pos = sim.drone_positions();
    QCOMPARE(got.size(), pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < pos.size(); ++j)
        if (j != i) best = std::min(best, salsa::distance(pos[i], pos[j]));
      QVERIFY2(got[i] == best || std::abs(got[i] - best) < 1e-9,
               qPrintable(QString("drone %1: %2, brute force %3").arg(i).arg(got[i]).arg(best)));
    }
  }

  // ---------------------------------------------------------------- static geometry
  void ray_casts_match_brute_force_data() {
    QTest::addColumn<int>("seed");
    QTest::addColumn<double>("size");
    QTest::addColumn<int>("shapes");
    QTest::addColumn<double>("cell");
    QTest::addColumn<double>("max_range");  // m: the longest rays
    QTest::newRow("obstacle range cells") << 1 << 500.0 << 200 << 50.2 << 1000.0;
    QTest::newRow("small cells, many shapes") << 2 << 300.0 << 600 << 5.0 << 200.0;
    QTest::newRow("cells larger than the map") << 3 << 100.0 << 50 << 1000.0 << 200.0;
    QTest::newRow("huge map, capped cell count") << 4 << 200000.0 << 400 << 1.0 << 5000.0;
  }
  void ray_casts_match_brute_force() {
    QFETCH(int, seed);
    QFETCH(double, size);
    QFETCH(int, shapes);
    QFETCH(double, cell);
    QFETCH(double, max_range);
    const salsa::MapData map = random_map(static_cast<std::uint64_t>(seed), size, shapes);
    const salsa::StaticGeometry g(map, cell);
    QVERIFY(g.segments().size() > 4 + static_cast<std::size_t>(shapes));
    salsa::Rng rng(static_cast<std::uint64_t>(seed), 1);
    std::vector<std::uint32_t> ids;
    int checked = 0, hit = 0;
    auto check = [&](Vec2 from, Vec2 dir, double range, const char* kind) {
      const auto expected = brute_ray(g, from, dir, range);
      g.candidates(from, range, ids);
      auto sorted = ids;  // each segment once
      std::sort(sorted.begin(), sorted.end());
      QVERIFY(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
      const auto fast = g.ray_cast(from, dir, range, ids);
      QVERIFY2(same_hit(fast, expected), qPrintable(QString("%1 ray from (%2, %3) along (%4, %5), %6 m: %7, brute force %8")
                                                        .arg(kind).arg(from.x, 0, 'g', 17).arg(from.y, 0, 'g', 17)
                                                        .arg(dir.x).arg(dir.y).arg(range).arg(show(fast)).arg(show(expected))));
      // The (from, to) overload: the same ray, ending at from + dir · range.
      const Vec2 to = from + dir * range;
      const double length = salsa::distance(from, to);
      const auto segment = g.ray_cast(from, to);
      const auto expected_segment = brute_ray(g, from, (to - from) / length, length);
      QVERIFY2(same_hit(segment, expected_segment),
               qPrintable(QString("%1 segment: %2, brute force %3").arg(kind).arg(show(segment)).arg(show(expected_segment))));
      ++checked;
      hit += expected.has_value();
    };
    const salsa::Rect b = map.bounds;
    const double ranges[] = {0.5, 10, 50.2, max_range / 3, max_range};
    for (int i = 0; i < 2000; ++i) {
      const Vec2 from = rng.in_rect(b);
      const double range = ranges[rng.index(5)];
      check(from, Vec2::polar(1, rng.angle()), range, "random");
      // Aimed exactly at a segment's end point, from within the longest range of it.
      const salsa::Segment& s = g.segments()[rng.index(g.segments().size())];
      const Vec2 end = rng.chance(0.5) ? s.a : s.b;
      Vec2 start = end + Vec2::polar(rng.uniform(0.01, 0.9) * max_range, rng.angle());
      start = {std::clamp(start.x, b.min.x, b.max.x), std::clamp(start.y, b.min.y, b.max.y)};
      if (start != end) check(start, (end - start).normalized(), max_range, "endpoint");
      // Parallel to the walls and the axis-aligned boxes, from whole-metre positions (on cell edges).
      const Vec2 axis = Vec2::polar(1, salsa::pi / 2 * static_cast<double>(rng.index(4)));
      const Vec2 dir{std::round(axis.x), std::round(axis.y)};
      check({std::floor(from.x), std::floor(from.y)}, dir, range, "axis");
      // Along a wall: starting on the boundary.
      check({b.min.x + std::floor(rng.uniform(0, b.width())), b.min.y}, Vec2{1, 0}, range, "along the wall");
    }
    qInfo("%d rays checked, %d hit", checked, hit);
    QVERIFY(hit > checked / 10);
  }

  void ray_segment_cases_data() {
    QTest::addColumn<Vec2>("from");
    QTest::addColumn<Vec2>("dir");
    QTest::addColumn<double>("range");
    QTest::addColumn<Vec2>("a");
    QTest::addColumn<Vec2>("b");
    QTest::addColumn<double>("expected");  // -1: no hit
    QTest::newRow("straight on") << Vec2{0, 0} << Vec2{1, 0} << 10.0 << Vec2{5, -1} << Vec2{5, 1} << 5.0;
    QTest::newRow("end point a") << Vec2{0, 0} << Vec2{1, 0} << 10.0 << Vec2{5, 0} << Vec2{5, 3} << 5.0;
    QTest::newRow("end point b") << Vec2{0, 0} << Vec2{1, 0} << 10.0 << Vec2{5, -3} << Vec2{5, 0} << 5.0;
    QTest::newRow("just past the end") << Vec2{0, 0} << Vec2{1, 0} << 10.0 << Vec2{5, 0.001} << Vec2{5, 3} << -1.0;
    QTest::newRow("exactly at range") << Vec2{0, 0} << Vec2{0, 1} << 5.0 << Vec2{-1, 5} << Vec2{1, 5} << 5.0;
    QTest::newRow("beyond range") << Vec2{0, 0} << Vec2{0, 1} << 4.999 << Vec2{-1, 5} << Vec2{1, 5} << -1.0;
    QTest::newRow("behind") << Vec2{0, 0} << Vec2{1, 0} << 10.0 << Vec2{-5, -1} << Vec2{-5, 1} << -1.0;
    QTest::newRow("parallel") << Vec2{0, 0} << Vec2{1, 0} << 10.0 << Vec2{1, 1} << Vec2{8, 1} << -1.0;
    QTest::newRow("collinear") << Vec2{0, 0} << Vec2{1, 0} << 10.0 << Vec2{2, 0} << Vec2{8, 0} << -1.0;
    QTest::newRow("starting on it") << Vec2{0, 0} << Vec2{1, 0} << 10.0 << Vec2{0, -1} << Vec2{0, 1} << 0.0;
    QTest::newRow("diagonal") << Vec2{0, 0} << Vec2{std::sqrt(0.5), std::sqrt(0.5)} << 100.0 << Vec2{10, 0} << Vec2{0, 10}
                              << std::sqrt(50.0);
  }
  void ray_segment_cases() {
    QFETCH(Vec2, from);
    QFETCH(Vec2, dir);
    QFETCH(double, range);
    QFETCH(Vec2, a);
    QFETCH(Vec2, b);
    QFETCH(double, expected);
    const auto t = salsa::ray_segment(from, dir, range, {a, b});
    if (expected < 0) {
      QVERIFY2(!t, qPrintable(QString("hit at %1").arg(t ? *t : 0)));
    } else {
      QVERIFY(t);
      QVERIFY2(std::abs(*t - expected) < 1e-12, qPrintable(QString::number(*t, 'g', 17)));
    }
    // A polygon around the parallel case: the ray still sees the walls that cross it.
    if (QByteArray(QTest::currentDataTag()) == "collinear") {
      salsa::MapData map;
      map.bounds = {{-20, -20}, {20, 20}};
      map.lines = {{{2, 0}, {8, 0}, {8, 5}}};
      const salsa::StaticGeometry g(map, 5);
      const auto hit = g.ray_cast(from, from + dir * 30);
      QVERIFY(hit);
      QCOMPARE(hit->distance, 8.0);  // the crossing wall at x = 8 (its end point), not the collinear one
    }
  }

  void is_free_matches_brute_force_data() {
    QTest::addColumn<int>("seed");
    QTest::addColumn<double>("cell");
    QTest::newRow("obstacle range cells") << 5 << 50.2;
    QTest::newRow("small cells") << 6 << 2.0;
    QTest::newRow("one cell") << 7 << 1e6;
  }
  void is_free_matches_brute_force() {
    QFETCH(int, seed);
    QFETCH(double, cell);
    const salsa::MapData map = random_map(static_cast<std::uint64_t>(seed), 400, 300);
    const salsa::StaticGeometry g(map, cell);
    salsa::Rng rng(static_cast<std::uint64_t>(seed), 2);
    auto brute = [&](Vec2 p, double clearance) {
      const salsa::Rect& b = map.bounds;
      if (p.x < b.min.x + clearance || p.x > b.max.x - clearance || p.y < b.min.y + clearance || p.y > b.max.y - clearance)
        return false;
      for (const auto& poly : map.obstacles)
        if (salsa::inside_polygon(p, poly)) return false;
      for (const salsa::Segment& s : g.segments())
        if (salsa::segment_distance(p, s) < clearance) return false;
      return true;
    };
    int free = 0, blocked = 0;
    for (int i = 0; i < 20000; ++i) {
      Vec2 p = rng.in_rect({{-10, -10}, {410, 410}});
      if (i % 4 == 0) p = {std::round(p.x), std::round(p.y)};  // on box corners and edges
      if (i % 4 == 1) {  // near a segment, at exactly the clearance sometimes
        const salsa::Segment& s = g.segments()[rng.index(g.segments().size())];
        p = s.a + (s.b - s.a) * rng.uniform() + Vec2::polar(rng.uniform(0, 3), rng.angle());
      }
      const double clearance = rng.chance(0.2) ? 0.0 : rng.uniform(0, 6);
      const bool expected = brute(p, clearance);
      QVERIFY2(g.is_free(p, clearance) == expected,
               qPrintable(QString("(%1, %2) clearance %3: brute force says %4").arg(p.x, 0, 'g', 17).arg(p.y, 0, 'g', 17)
                              .arg(clearance).arg(expected)));
      (expected ? free : blocked)++;
    }
    qInfo("%d free, %d blocked", free, blocked);
    QVERIFY(free > 1000 && blocked > 1000);
  }

  /// is_free finds solids from its grid (a ray along one row of cells), not by testing every obstacle:
  /// the same answers as inside_polygon on each, on maps made to trip it: vertices and edges on cell
  /// lines, overlapping and nested solids, one long concave polygon crossing many cells, points on
  /// vertices' heights.
  void inside_solid_matches_brute_force_data() {
    QTest::addColumn<int>("seed");
    QTest::addColumn<double>("cell");
    QTest::newRow("cells of 4 m, corners on cell lines") << 21 << 4.0;
    QTest::newRow("cells of 1 m") << 22 << 1.0;
    QTest::newRow("cells of 7.3 m") << 23 << 7.3;
    QTest::newRow("one cell") << 24 << 1e6;
  }
  void inside_solid_matches_brute_force() {
    QFETCH(int, seed);
    QFETCH(double, cell);
    salsa::Rng rng(static_cast<std::uint64_t>(seed), 0);
    salsa::MapData map;
    map.bounds = {{-100, -100}, {100, 100}};
    map.spawn = {0, 0};
    const salsa::Rect inner{{-90, -90}, {90, 90}};
    for (int i = 0; i < 150; ++i) {
      const Vec2 c = rng.in_rect(inner);
      if (i % 3 == 0) {  // boxes on whole multiples of 4 m: on the cell lines of the 4 m and 1 m grids
        const double x = 4 * std::floor(c.x / 4), y = 4 * std::floor(c.y / 4);
        const double w = std::min({4.0 * (1 + static_cast<double>(rng.index(4))), 100 - x, 100 - y});  // within the bounds, as check_map demands
        map.obstacles.push_back({{x, y}, {x + w, y}, {x + w, y + w}, {x, y + w}});
      } else {
        map.obstacles.push_back(random_polygon(rng, c, rng.uniform(0.5, 15), map.bounds));  // they overlap
      }
    }
    salsa::Polyline comb;  // a concave comb across the map: many edges straddle most rows
    for (int k = 0; k < 40; ++k) {
      const double x = -80 + 4 * k;
      comb.push_back({x, -60});
      comb.push_back({x + 2, 60});
    }
    comb.push_back({80, -70});
    comb.push_back({-80, -70});
    map.obstacles.push_back(comb);
    const salsa::StaticGeometry g(map, cell);
    std::vector<Vec2> vertices;
    for (const auto& poly : map.obstacles) vertices.insert(vertices.end(), poly.begin(), poly.end());
    int inside = 0, outside = 0;
    for (int i = 0; i < 40000; ++i) {
      Vec2 p = rng.in_rect({{-101, -101}, {101, 101}});
      if (i % 4 == 0) p = {std::round(p.x), std::round(p.y)};           // on cell lines and box edges
      if (i % 4 == 1) p.y = vertices[rng.index(vertices.size())].y;      // level with a vertex
      if (i % 8 == 2) p = vertices[rng.index(vertices.size())];          // on a vertex
      bool expected = map.bounds.contains(p);
      for (const auto& poly : map.obstacles)
        if (salsa::inside_polygon(p, poly)) expected = false;
      QVERIFY2(g.is_free(p, 0) == expected,
               qPrintable(QString("(%1, %2): brute force says %3").arg(p.x, 0, 'g', 17).arg(p.y, 0, 'g', 17).arg(expected)));
      (expected ? outside : inside)++;
    }
    qInfo("%d inside a solid or out of bounds, %d free", inside, outside);
    QVERIFY(inside > 5000 && outside > 5000);
  }

  /// 40,000 obstacles (the area_coverage case that took 28 s): a free-space query reads one row of
  /// cells, so 200,000 queries take well under a second where testing every obstacle took minutes.
  /// Not a timed test: a scan of every obstacle (8·10^9 polygon tests) would not finish within the
  /// suite's time limit; the figure is printed, and docs/reliability.md has the measured one.
  void is_free_with_many_obstacles_is_fast() {
    salsa::MapData map;
    map.bounds = {{0, 0}, {2000, 2000}};
    map.spawn = {1, 1};
    for (int i = 0; i < 200; ++i)
      for (int j = 0; j < 200; ++j) {
        const double x = 10.0 * i + 3, y = 10.0 * j + 3;
        map.obstacles.push_back({{x, y}, {x + 4, y}, {x + 4, y + 4}, {x, y + 4}});
      }
    const salsa::StaticGeometry g(map, 50);
    salsa::Rng rng(3, 0);
    QElapsedTimer timer;
    timer.start();
    int free = 0;
    for (int i = 0; i < 200000; ++i) free += g.is_free(rng.in_rect(map.bounds), 0);
    const auto ms = timer.elapsed();
    qInfo("200000 queries among 40000 obstacles: %lld ms, %d free", static_cast<long long>(ms), free);
    QVERIFY(free > 0.8 * 200000 && free < 0.9 * 200000);  // 16 % of the map is obstacle
  }

  /// crossing_edges compares only edges that share a grid cell when a polygon has more than 64 vertices:
  /// the same first crossing pair as comparing every pair, on simple polygons, polygons with crossings
  /// added, folds and repeated vertices.
  void crossing_edges_matches_brute_force() {
    auto brute = [](const salsa::Polyline& poly) -> std::pair<std::size_t, std::size_t> {
      const std::size_t n = poly.size();
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
          const Vec2 a = poly[i], b = poly[(i + 1) % n], c = poly[j], d = poly[(j + 1) % n];
          if (j == i + 1 || (i == 0 && j == n - 1)) {
            const Vec2 shared = j == i + 1 ? b : a, oi = j == i + 1 ? a : b, oj = j == i + 1 ? d : c;
            if ((oi - shared).cross(oj - shared) == 0 && (oi - shared).dot(oj - shared) > 0) return {i, j};
            continue;
          }
          if (salsa::segments_touch(a, b, c, d)) return {i, j};
        }
      return {0, 0};
    };
    salsa::Rng rng(31, 0);
    int crossing = 0, simple = 0;
    for (int round = 0; round < 300; ++round) {
      const std::size_t n = 65 + rng.index(400);
      salsa::Polyline poly;  // star-shaped around the origin: simple
      for (std::size_t k = 0; k < n; ++k) {
        Vec2 v = Vec2::polar(rng.uniform(20, 100), 2 * salsa::pi * static_cast<double>(k) / static_cast<double>(n));
        if (round % 5 == 0) v = {std::round(v.x), std::round(v.y)};  // whole metres: touching and collinear edges
        poly.push_back(v);
      }
      switch (round % 4) {
        case 1: poly[rng.index(n)] = Vec2::polar(150, rng.angle()); break;  // a spike out across its neighbours
        case 2: std::swap(poly[rng.index(n)], poly[rng.index(n)]); break;   // two vertices swapped
        case 3: poly[rng.index(n)] = poly[rng.index(n)]; break;             // a vertex repeated
        default: break;
      }
      const auto expected = brute(poly);
      QCOMPARE(salsa::crossing_edges(poly), expected);
      (expected.first != expected.second ? crossing : simple)++;
    }
    qInfo("%d crossing, %d simple", crossing, simple);
    QVERIFY(crossing > 50 && simple > 50);
  }

  /// A polygon of 10^6 vertices (the map creator never opened one: every pair of edges was compared).
  /// Not a timed test: comparing every pair (5·10^11) would not finish within the suite's time limit.
  void crossing_edges_of_a_million_vertices_is_fast() {
    salsa::Polyline poly;
    salsa::Rng rng(32, 0);
#if defined(__SANITIZE_ADDRESS__)
    const std::size_t n = 200'000;  // ten times slower under the sanitizers; still 2·10^10 pairs by brute force
#else
    const std::size_t n = 1'000'000;
#endif
    for (std::size_t k = 0; k < n; ++k)
    {  // a wavy outline with a little noise: short edges, as a traced shape has
      const double angle = 2 * salsa::pi * static_cast<double>(k) / static_cast<double>(n);
      poly.push_back(Vec2::polar(750 + 200 * std::sin(7 * angle) + rng.uniform(0, 0.001), angle));
    }
    QElapsedTimer timer;
    timer.start();
    QCOMPARE(salsa::crossing_edges(poly), (std::pair<std::size_t, std::size_t>{0, 0}));
    poly[1000] = {2000, 2000};  // out and back across its neighbours' edges
    const auto [i, j] = salsa::crossing_edges(poly);
    QVERIFY(i != j);
    qInfo("two checks of %zu vertices: %lld ms", n, static_cast<long long>(timer.elapsed()));
  }

  // ---------------------------------------------------------------- parallel decide
  void parallel_decide_equals_serial_data() {
    QTest::addColumn<QString>("behavior");  // "" for the test's own
    QTest::newRow("jitter") << "";
    for (const auto& e : host_->behaviors()) QTest::newRow(e.factory.name.c_str()) << q(e.factory.name);
  }
  void parallel_decide_equals_serial() {
    QFETCH(QString, behavior);
    auto positions_after = [&](int threads) {
      salsa::SimulationSetup setup;
      if (behavior.isEmpty()) {
        setup.map = random_map(11, 600, 60);
        setup.groups[0].behavior = std::make_shared<Jitter>();
        setup.groups[0].drones = 300;
        setup.groups[0].spawn_mode = salsa::SpawnMode::uniform;
        setup.seed = 5;
      } else {
        const salsa::TestSpec t = salsa::parse_test(
            QString(R"({"behavior": "%1", "drones": 300, "map": {"name": "forest", "params": {"size": 600}}, "seed": 5})")
                .arg(behavior).toStdString(),
            "parallel", *host_);
        setup = salsa::make_setup(t, *host_);
      }
      setup.threads = threads;
      salsa::Simulation sim(setup);
      sim.run_steps(200);
      return std::vector<Vec2>(sim.drone_positions().begin(), sim.drone_positions().end());
    };
    const auto serial = positions_after(1), parallel = positions_after(2);
    QCOMPARE(serial.size(), parallel.size());
    for (std::size_t i = 0; i < serial.size(); ++i)
      QVERIFY2(serial[i] == parallel[i], qPrintable(QString("drone %1 differs").arg(i)));
  }
};

QTEST_GUILESS_MAIN(TestFastPaths)
#include "test_fast_paths.moc"
