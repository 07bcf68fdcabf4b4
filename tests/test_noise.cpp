// Sensor noise (the drone properties position_noise, neighbour_noise, obstacle_noise, miss_probability
// and false_detection_rate): what a drone perceives departs from the truth by the declared laws, the
// contact handlers and the outputs keep the truth, the draws come from the seed alone (any thread
// count, any behavior), and zero noise changes nothing.
#include <QJsonDocument>
#include <QJsonObject>
#include <QTemporaryDir>
#include <QtTest>

#include <cmath>
#include <functional>
#include <map>

#include "common.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/run/runner.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

/// Mean and standard deviation of a sample.
struct Sample {
  double n = 0, sum = 0, squares = 0;
  void add(double x) { n += 1, sum += x, squares += x * x; }
  double mean() const { return sum / n; }
  double sd() const { return std::sqrt((squares - sum * sum / n) / (n - 1)); }
};

/// Empty when `s` fits N(0, sd²): its mean within 4 standard errors (sd/√n) of 0 and its sd within 4
/// standard errors of a normal sample's sd (sd/√(2n)) of sd; else what does not.
QString normal_problem(const Sample& s, double sd, const char* what) {
  if (s.n < 1000) return QString("%1: only %2 draws").arg(what).arg(s.n);
  if (std::abs(s.mean()) > 4 * sd / std::sqrt(s.n)) return QString("%1: mean %2 for sd %3 over %4 draws").arg(what).arg(s.mean()).arg(sd).arg(s.n);
  if (std::abs(s.sd() - sd) > 4 * sd / std::sqrt(2 * s.n)) return QString("%1: sd %2, not %3, over %4 draws").arg(what).arg(s.sd()).arg(sd).arg(s.n);
  return {};
}

/// Hovers (cancels its velocity) and hands each decision's perception to `on_decide`. The suites run it
/// on one thread, so on_decide may write shared state.
class Recorder final : public Behavior {
 public:
  std::function<void(const Perception&)> on_decide = [](const Perception&) {};
  Vec2 steering;  ///< added to the hover: a drone that flies instead
  Vec2 decide(const Perception& me, Rng&) override {
    on_decide(me);
    return steering - me.velocity;
  }
};

/// Targets exactly where the test puts them.
class FixedTargets final : public TargetKind {
 public:
  explicit FixedTargets(std::vector<Vec2> points) : points_(std::move(points)) {}
  double radius() const override { return 0; }
  std::vector<Vec2> place(std::size_t, const WorldView&, Rng&) const override { return points_; }

 private:
  std::vector<Vec2> points_;
};

/// Marks every target it is told about found (as detect_targets does), and records the events by step:
/// a phantom handed to it would fail the test (mark_found refuses an id that is no target).
class Finder final : public ContactHandler {
 public:
  std::map<std::uint64_t, std::vector<std::uint32_t>> seen;  ///< step → target ids in view, in order
  double dt = 0.1;
  void on_contact(const ContactEvent& e, ContactActions& actions) override {
    if (e.kind != ContactKind::target_in_view) return;
    seen[static_cast<std::uint64_t>(std::llround(e.time / dt)) - 1].push_back(e.other);
    actions.mark_found(e.other, e.drone);
  }
};

/// `drones` hovering drones spread uniformly over an empty square map of `size` m, dt 0.1 s, one thread.
SimulationSetup field(std::size_t drones, double size, std::shared_ptr<Behavior> behavior) {
  SimulationSetup s;
  s.map.bounds = {{0, 0}, {size, size}};
  s.map.spawn = {size / 2, size / 2};
  s.groups[0].drones = drones;
  s.groups[0].behavior = std::move(behavior);
  s.groups[0].spawn_mode = SpawnMode::uniform;
  s.dt = 0.1;
  s.threads = 1;
  return s;
}


const QStringList data_files{"config.json", "map.json", "summary.csv", "drones.csv", "targets.csv", "outcome.csv"};

}  // namespace

class TestNoise : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

  QString run(const std::string& json, const QString& out, int threads = 1) {
    const TestSpec test = parse_test(json, "noise.json", *host_);
    RunOptions options;
    options.out = out.toStdString();
    options.threads = threads;
    return q(run_test(test, *host_, options).folder);
  }

 private Q_SLOTS:
  // Each neighbour's perceived position is its true one plus N(0, sd²) on each axis, the axes
  // uncorrelated, fresh every step; the distance is recomputed from it; the drone's own position stays true.
  void neighbour_noise_is_gaussian_around_the_truth() {
    auto recorder = std::make_shared<Recorder>();
    SimulationSetup s = field(30, 300, recorder);
    s.groups[0].drone.neighbour_noise = 2;
    Sample x, y, xy;
    int inconsistent = 0, own_moved = 0, repeated = 0;
    std::map<std::pair<std::uint32_t, std::uint32_t>, Vec2> last;  // (drone, neighbour) → last step's error
    recorder->on_decide = [&](const Perception& me) {
      const auto truth = me.world->drone_positions();
      own_moved += me.position != truth[me.id];
      for (const Neighbour& n : me.neighbours) {
        const Vec2 e = n.position - truth[n.id];
        x.add(e.x), y.add(e.y), xy.add(e.x * e.y);
        inconsistent += std::abs(n.distance - distance(n.position, me.position)) > 1e-9;
        Vec2& before = last[{me.id, n.id}];
        repeated += before == e;
        before = e;
      }
    };
    Simulation sim(s);
    sim.run_steps(40);
    QVERIFY2(normal_problem(x, 2, "x").isEmpty(), qPrintable(normal_problem(x, 2, "x")));
    QVERIFY2(normal_problem(y, 2, "y").isEmpty(), qPrintable(normal_problem(y, 2, "y")));
    // E[xy] = 0 with sd σ² per draw: the two halves of each pair are independent.
    QVERIFY2(std::abs(xy.mean()) < 4 * 4 / std::sqrt(xy.n), qPrintable(QString("E[xy] = %1").arg(xy.mean())));
    QCOMPARE(inconsistent, 0);
    QCOMPARE(own_moved, 0);
    QCOMPARE(repeated, 0);
  }

  // The own position is off by N(0, sd²) per axis; everything sensed moves with it (measured from where
  // the drone is, placed around where it believes it is): neighbour offsets, distances and ray hits stay
  // exact. perceived_position() tells beforehand what the next decision will see.
  void own_position_noise_moves_the_whole_picture() {
    auto recorder = std::make_shared<Recorder>();
    SimulationSetup s = field(200, 150, recorder);
    s.groups[0].drone.position_noise = 3;
    s.groups[0].drone.detection_range = 20;
    const Simulation* sim = nullptr;
    Sample x, y;
    int offsets_off = 0, hits_off = 0, hits = 0, predicted_off = 0;
    std::vector<Vec2> predicted;
    recorder->on_decide = [&](const Perception& me) {
      const auto truth = me.world->drone_positions();
      const Vec2 error = me.position - truth[me.id];
      x.add(error.x), y.add(error.y);
      if (!predicted.empty()) predicted_off += me.position != predicted[me.id];
      for (const Neighbour& n : me.neighbours)
        offsets_off += distance(n.position - me.position, truth[n.id] - truth[me.id]) > 1e-9 ||
                       std::abs(n.distance - distance(truth[n.id], truth[me.id])) > 1e-9;
      const auto true_hits = sim->obstacle_hits(me.id);
      hits_off += true_hits.size() != me.obstacles.size();
      for (std::size_t k = 0; k < std::min(true_hits.size(), me.obstacles.size()); ++k, ++hits) {
        const ObstacleHit& h = me.obstacles[k];
        hits_off += h.distance != true_hits[k].distance ||
                    distance(h.point - me.position, true_hits[k].point - truth[me.id]) > 1e-9;
      }
    };
    Simulation simulation(s);
    sim = &simulation;
    for (int step = 0; step < 50; ++step) {
      predicted.clear();
      for (std::uint32_t i = 0; i < simulation.drone_count(); ++i) predicted.push_back(simulation.perceived_position(i));
      simulation.step();
    }
    QVERIFY2(normal_problem(x, 3, "x").isEmpty(), qPrintable(normal_problem(x, 3, "x")));
    QVERIFY2(normal_problem(y, 3, "y").isEmpty(), qPrintable(normal_problem(y, 3, "y")));
    QCOMPARE(offsets_off, 0);
    QVERIFY2(hits > 1000, "drones near the walls of a 150 m map see them");
    QCOMPARE(hits_off, 0);
    QCOMPARE(predicted_off, 0);
  }

  // Each ray's hit distance is off by N(0, sd²), the point moved along the ray to match, clamped to
  // [0, obstacle_range]; rays that hit nothing stay out.
  void ray_noise_is_gaussian_along_the_ray() {
    auto recorder = std::make_shared<Recorder>();
    SimulationSetup s = field(40, 100, recorder);
    s.groups[0].drone.obstacle_noise = 0.5;
    const Simulation* sim = nullptr;
    Sample error;
    int off_ray = 0, off_count = 0, outside = 0;
    recorder->on_decide = [&](const Perception& me) {
      const auto true_hits = sim->obstacle_hits(me.id);
      off_count += true_hits.size() != me.obstacles.size();
      for (std::size_t k = 0; k < std::min(true_hits.size(), me.obstacles.size()); ++k) {
        const ObstacleHit& h = me.obstacles[k];
        const ObstacleHit& t = true_hits[k];
        outside += h.distance < 0 || h.distance > me.obstacle_range;
        // Along the true ray, at the noisy distance.
        const Vec2 along = t.distance > 0 ? (t.point - me.position) * (h.distance / t.distance) : Vec2{};
        off_ray += distance(h.point, me.position + along) > 1e-9;
        if (t.distance > 3 && t.distance < me.obstacle_range - 3) error.add(h.distance - t.distance);  // 6 sd from the clamps
      }
    };
    Simulation simulation(s);
    sim = &simulation;
    simulation.run_steps(100);
    QVERIFY2(normal_problem(error, 0.5, "hit distance").isEmpty(), qPrintable(normal_problem(error, 0.5, "hit distance")));
    QCOMPARE(off_count, 0);
    QCOMPARE(off_ray, 0);
    QCOMPARE(outside, 0);

    // A noise far larger than the range: every distance clamped into [0, range], both ends reached.
    SimulationSetup wide = field(40, 100, recorder);
    wide.groups[0].drone.obstacle_noise = 500;
    int at_zero = 0, at_range = 0;
    outside = 0;
    recorder->on_decide = [&](const Perception& me) {
      for (const ObstacleHit& h : me.obstacles) {
        outside += h.distance < 0 || h.distance > me.obstacle_range;
        at_zero += h.distance == 0, at_range += h.distance == me.obstacle_range;
      }
    };
    Simulation clamped(wide);
    clamped.run_steps(20);
    QCOMPARE(outside, 0);
    QVERIFY(at_zero > 100 && at_range > 100);
  }

  // A target in view is missed with the declared probability (within its binomial interval), and a
  // missed one reaches neither the behavior nor the contact handlers: both hear of the same targets.
  void missed_targets_reach_no_one() {
    std::vector<Vec2> points;
    for (int k = 0; k < 20; ++k) points.push_back({10.0 + 4 * k, 30.0 + k});
    auto recorder = std::make_shared<Recorder>();
    SimulationSetup s = field(1, 100, recorder);
    s.groups[0].drone.camera_range = 500;  // every target in view from anywhere
    s.groups[0].drone.miss_probability = 0.25;
    s.target_kind = std::make_shared<FixedTargets>(points);
    s.targets = points.size();
    auto finder = std::make_shared<Finder>();
    s.contact_handlers = {finder};
    std::map<std::uint64_t, std::vector<std::uint32_t>> perceived;
    std::uint64_t step = 0;
    recorder->on_decide = [&](const Perception& me) {
      for (const TargetSeen& t : me.targets) perceived[step].push_back(t.id);
    };
    Simulation sim(s);
    for (; step < 500; ++step) sim.step();
    double detected = 0;
    for (const auto& [k, ids] : perceived) detected += static_cast<double>(ids.size());
    const double trials = 500.0 * 20, p = 0.75;
    QVERIFY2(std::abs(detected / trials - p) < 4 * std::sqrt(p * (1 - p) / trials), qPrintable(QString("%1 of %2 detected").arg(detected).arg(trials)));
    QCOMPARE(finder->seen, perceived);
    for (const TargetState& t : sim.targets()) QVERIFY(t.found());  // 500 steps at 3/4: every one seen at last
    std::uint64_t sightings_of_0 = 0;  // a missed target is not observed either
    for (const auto& [k, ids] : perceived) sightings_of_0 += static_cast<std::uint64_t>(std::count(ids.begin(), ids.end(), 0u));
    QCOMPARE(sim.targets()[0].observations, sightings_of_0);

    // Probability 1: nothing is ever seen, nothing found.
    SimulationSetup blind = s;
    blind.groups[0].drone.miss_probability = 1;
    auto none = std::make_shared<Finder>();
    blind.contact_handlers = {none};
    perceived.clear();
    Simulation blind_sim(blind);
    blind_sim.run_steps(50);
    QVERIFY(none->seen.empty() && perceived.empty());
    QCOMPARE(blind_sim.targets_found(), std::size_t(0));
  }

  // False detections come at their Poisson rate per drone (the count and the share of steps without
  // any), uniformly over the camera's disc, with the phantom id, never found, never handed to a
  // contact handler, and counted by the simulation.
  void false_detections_are_poisson_and_reach_no_handler() {
    auto recorder = std::make_shared<Recorder>();
    SimulationSetup s = field(50, 300, recorder);
    s.groups[0].drone.false_detection_rate = 2;  // 0.2 per drone and step of 0.1 s
    s.groups[0].drone.camera_range = 15;
    std::vector<Vec2> points;
    for (int k = 0; k < 30; ++k) points.push_back({5.0 + 9.5 * k, 150});
    s.target_kind = std::make_shared<FixedTargets>(points);
    s.targets = points.size();
    auto finder = std::make_shared<Finder>();
    s.contact_handlers = {finder};
    double phantoms = 0, empty_steps = 0, decisions = 0;
    Sample spread;  // d²/R²: uniform in [0, 1] for points uniform over the disc
    int bad = 0, real_after_phantom = 0;
    recorder->on_decide = [&](const Perception& me) {
      double mine = 0;
      bool phantom_before = false;
      for (const TargetSeen& t : me.targets) {
        if (t.id != TargetSeen::phantom) {
          real_after_phantom += phantom_before;
          continue;
        }
        phantom_before = true;
        ++mine;
        bad += t.found || t.distance > me.camera_range || std::abs(t.distance - distance(t.position, me.position)) > 1e-9;
        spread.add(t.distance * t.distance / (me.camera_range * me.camera_range));
      }
      phantoms += mine, empty_steps += mine == 0, ++decisions;
    };
    Simulation sim(s);
    sim.run_steps(200);
    const double mean = 2 * 0.1 * decisions;  // 2000
    QVERIFY2(std::abs(phantoms - mean) < 4 * std::sqrt(mean), qPrintable(QString("%1 false detections, %2 expected").arg(phantoms).arg(mean)));
    QCOMPARE(static_cast<double>(sim.false_detections()), phantoms);
    const double p0 = std::exp(-0.2);  // no false detection in a step (a Bernoulli draw would give 0.8)
    QVERIFY2(std::abs(empty_steps / decisions - p0) < 4 * std::sqrt(p0 * (1 - p0) / decisions),
             qPrintable(QString("%1 of %2 steps without").arg(empty_steps).arg(decisions)));
    QVERIFY2(std::abs(spread.mean() - 0.5) < 4 * std::sqrt(1.0 / 12 / spread.n), qPrintable(QString("E[d²/R²] = %1").arg(spread.mean())));
    QCOMPARE(bad, 0);
    QCOMPARE(real_after_phantom, 0);  // the true targets first, then the phantoms
    std::size_t events = 0;
    for (const auto& [step, ids] : finder->seen) events += ids.size();
    QVERIFY2(events > 0, "the drones over the row of targets see some");
    QVERIFY(sim.targets_found() <= points.size());
  }

  // Noise draws are the seed's, per step and drone, not the behavior's: a drone that flies and one
  // that hovers have the same position errors and false detections at every step.
  void noise_is_paired_across_behaviors() {
    using Draws = std::map<std::pair<long, std::uint32_t>, std::vector<Vec2>>;  // (step, drone) → position error, phantoms
    auto draws = [](Vec2 steering) {
      auto recorder = std::make_shared<Recorder>();
      recorder->steering = steering;
      SimulationSetup s = field(20, 300, recorder);
      s.groups[0].drone.position_noise = 1;
      s.groups[0].drone.false_detection_rate = 3;
      Draws out;
      recorder->on_decide = [&](const Perception& me) {
        std::vector<Vec2>& mine = out[{std::lround(me.time / me.dt), me.id}];
        mine.push_back(me.position - me.world->drone_positions()[me.id]);
        for (const TargetSeen& t : me.targets) mine.push_back(t.position - me.position);
      };
      Simulation sim(s);
      sim.run_steps(30);
      return out;
    };
    const Draws hovering = draws({}), flying = draws({0.5, 0.2});
    QCOMPARE(hovering.size(), std::size_t(20 * 30));
    std::size_t phantoms = 0;
    for (const auto& [key, mine] : hovering) phantoms += mine.size() - 1;
    QVERIFY(phantoms > 100);  // 0.3 per drone and step
    // The same draws (up to rounding: the error is read back as perceived − true, at other positions).
    int differ = 0;
    for (const auto& [key, mine] : hovering) {
      const std::vector<Vec2>& theirs = flying.at(key);
      differ += mine.size() != theirs.size();
      for (std::size_t k = 0; k < std::min(mine.size(), theirs.size()); ++k) differ += distance(mine[k], theirs[k]) > 1e-9;
    }
    QCOMPARE(differ, 0);
  }

  // Every kind of noise on: the same bytes on 1 and 2 threads (over 64 drones, so decide is parallel),
  // config.json records the noise and reruns to the same bytes, the flight differs from noise-free, and
  // the false_detections column counts what the simulation counted.
  void noisy_runs_are_deterministic_and_counted() {
    const std::string common = R"({"name": "n", "behavior": "flocking", "drones": 100, "map": {"name": "forest", "params": {"size": 300}},
        "targets": {"count": 60}, "time": 10, "seed": 3)";
    const std::string noisy = common + R"(, "drone": {"position_noise": 1.5, "neighbour_noise": 2, "obstacle_noise": 0.5,
        "miss_probability": 0.3, "false_detection_rate": 0.5}})", plain = common + "}";
    QTemporaryDir one, two, rerun, quiet;
    const QString a = run(noisy, one.path(), 1), b = run(noisy, two.path(), 2);
    for (const QString& file : data_files) QVERIFY2(read_file(a + "/" + file) == read_file(b + "/" + file), qPrintable(file));
    QVERIFY(read_file(a + "/config.json").contains("\"false_detection_rate\": 0.5"));
    const TestSpec again = load_tests((a + "/config.json").toStdString(), *host_)[0];
    RunOptions options;
    options.out = rerun.path().toStdString();
    QCOMPARE(read_file(q(run_test(again, *host_, options).folder) + "/drones.csv"), read_file(a + "/drones.csv"));
    const QString c = run(plain, quiet.path());
    QVERIFY(read_file(a + "/drones.csv") != read_file(c + "/drones.csv"));
    // The count: cumulative in summary.csv, its last value in outcome.csv; absent without a rate.
    const auto summary = rows_of(a + "/summary.csv"), outcome = rows_of(a + "/outcome.csv");
    QCOMPARE(summary[0].back(), std::string("false_detections"));
    for (std::size_t r = 2; r < summary.size(); ++r) QVERIFY(std::stoul(summary[r].back()) >= std::stoul(summary[r - 1].back()));
    QCOMPARE(outcome[0].back(), std::string("false_detections"));
    QCOMPARE(outcome[1].back(), summary.back().back());
    const double expected = 100 * 0.5 * 10;  // drones × rate × time
    QVERIFY(std::abs(std::stod(outcome[1].back()) - expected) < 4 * std::sqrt(expected));
    QVERIFY(!read_file(c + "/summary.csv").contains("false_detections") && !read_file(c + "/outcome.csv").contains("false_detections"));
  }

  // A rate switched on by a timed change: the column is there from the start, 0 until the change.
  void a_timed_change_brings_the_column() {
    QTemporaryDir out;
    const QString dir = run(R"({"name": "c", "behavior": "random_walk", "drones": 10, "time": 6, "log_interval": 1,
        "changes": [{"time": 3, "set": {"drone.false_detection_rate": 2}}]})", out.path());
    const auto summary = rows_of(dir + "/summary.csv");
    QCOMPARE(summary[0].back(), std::string("false_detections"));
    QCOMPARE(summary[3].back(), std::string("0"));  // t = 2 s
    QVERIFY(std::stoul(summary.back().back()) > 0);
  }

  // Noise properties written as 0 are no noise: every file byte for byte as without them.
  void zero_noise_is_no_noise() {
    const std::string common = R"("name": "z", "behavior": "pheromone_avoidance", "drones": 20,
        "map": {"name": "forest", "params": {"size": 300}}, "targets": {"count": 80}, "time": 10, "seed": 9)";
    QTemporaryDir plain, zeros;
    const QString a = run("{" + common + "}", plain.path());
    const QString b = run("{" + common + R"(, "drone": {"base": "small", "position_noise": 0, "neighbour_noise": 0, "obstacle_noise": 0,
        "miss_probability": 0, "false_detection_rate": 0}})", zeros.path());
    for (const QString& file : data_files)
      if (file != "config.json") QVERIFY2(read_file(a + "/" + file) == read_file(b + "/" + file), qPrintable(file));
    // config.json too, but for the drone's name: an edited drone is "small-custom" whatever the edit.
    auto without_name = [](const QString& file) {
      QJsonObject config = QJsonDocument::fromJson(read_file(file)).object(), drone = config["drone"].toObject();
      drone.remove("name");
      config["drone"] = drone;
      return config;
    };
    QCOMPARE(without_name(b + "/config.json"), without_name(a + "/config.json"));
    QVERIFY(!read_file(b + "/config.json").contains("position_noise") && !read_file(b + "/config.json").contains("miss_probability") &&
            !read_file(b + "/config.json").contains("false_detection_rate"));
  }

  // Out of range or non-finite: refused before anything runs, one line naming the field and range.
  void bad_values_are_refused_data() {
    QTest::addColumn<QString>("drone");
    QTest::addColumn<QString>("start");  // the line starts so
    QTest::addColumn<QString>("range");  // and ends with the allowed range
    QTest::newRow("negative sd") << R"("position_noise": -1)" << "noise.json: drone.position_noise: -1" << "(allowed: [0, 1000] m)";
    QTest::newRow("huge sd") << R"("neighbour_noise": 1e300)" << "noise.json: drone.neighbour_noise: 1e+300" << "(allowed: [0, 1000] m)";
    QTest::newRow("probability above 1") << R"("miss_probability": 1.5)" << "noise.json: drone.miss_probability: 1.5" << "(allowed: [0, 1])";
    QTest::newRow("negative rate") << R"("false_detection_rate": -0.1)" << "noise.json: drone.false_detection_rate: -0.1" << "(allowed: [0, 100] 1/s)";
    QTest::newRow("negative ray sd") << R"("obstacle_noise": -0.5)" << "noise.json: drone.obstacle_noise: -0.5" << "(allowed: [0, 1000] m)";
  }
  void bad_values_are_refused() {
    QFETCH(QString, drone);
    QFETCH(QString, start);
    QFETCH(QString, range);
    try {
      parse_test(R"({"behavior": "flocking", "drone": {)" + drone.toStdString() + "}}", "noise.json", *host_);
      QFAIL("accepted");
    } catch (const InputError& e) {
      const QString what = e.what();
      QVERIFY2(what.startsWith(start) && what.endsWith(range) && !what.contains('\n'), qPrintable(what));
    }
  }
  void bad_changes_are_refused() {
    try {
      parse_test(R"({"behavior": "flocking", "changes": [{"time": 1, "set": {"drone.miss_probability": 2}}]})", "noise.json", *host_);
      QFAIL("accepted");
    } catch (const InputError& e) {
      const QString what = e.what();
      QVERIFY2(what.contains("drone.miss_probability") && what.contains("[0, 1]") && !what.contains('\n'), qPrintable(what));
    }
  }
};

QTEST_MAIN(TestNoise)
#include "test_noise.moc"
