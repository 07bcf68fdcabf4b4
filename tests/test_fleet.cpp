// Groups, batteries and failures (the fleet model): what a researcher relies on when a swarm is not one
// group of drones that never fail — per-group outputs, one group's change touching only it, paired
// failure times, memory kept when others drop out, energy against the power model's integral.
#include <QRegularExpression>
#include <QTemporaryDir>
#include <QtTest>

#include <cmath>

#include "common.hpp"
#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

/// Counts its own decisions in its memory and flies at a fixed velocity: what a drone remembers is
/// visible through inspect(id), and its trajectory is known in advance.
class Counter final : public BehaviorWithMemory<int> {
 public:
  explicit Counter(Vec2 velocity = {}) : velocity_(velocity) {}
  Vec2 decide(const Perception& me, int& decisions, Rng&) override {
    ++decisions;
    return velocity_ - me.velocity;  // exactly this velocity from the next step on
  }
  std::string inspect(std::uint32_t id) const override { return id < memory().size() ? std::to_string(memory()[id]) : ""; }

 private:
  Vec2 velocity_;
};

SimulationSetup open_field(std::size_t drones, std::shared_ptr<Behavior> behavior) {
  SimulationSetup s;
  s.map.bounds = {{0, 0}, {2000, 2000}};
  s.map.spawn = {1000, 1000};
  s.groups[0].drones = drones;
  s.groups[0].behavior = std::move(behavior);
  s.groups[0].spawn_radius = 50;
  s.dt = 0.1;
  return s;
}


}  // namespace

class TestFleet : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

  QString run(const std::string& json, QTemporaryDir& out) {
    const TestSpec test = parse_test(json, "fleet.json", *host_);
    RunOptions options;
    options.out = out.path().toStdString();
    run_test(test, *host_, options);
    return out.path() + "/" + q(test.name);
  }

 private Q_SLOTS:
  // "groups" with one group is today's single form: the same seed and the same data, byte for byte.
  void one_group_is_the_single_form() {
    const std::string common = R"("map": {"name": "forest", "params": {"size": 400}}, "targets": {"count": 200}, "time": 20)";
    QTemporaryDir a, b;
    const QString single = run(R"({"name": "t", "behavior": "flocking", "drones": 8, "drone": "medium", )" + common + "}", a);
    const QString grouped =
        run(R"({"name": "t", "groups": [{"name": "scouts", "behavior": "flocking", "drones": 8, "drone": "medium"}], )" + common + "}", b);
    for (const char* file : {"summary.csv", "drones.csv", "targets.csv", "outcome.csv", "map.json"})
      QVERIFY2(read_file(single + "/" + file) == read_file(grouped + "/" + file), file);
    QVERIFY(!QFile::exists(single + "/fleet.csv") && !QFile::exists(grouped + "/fleet.csv"));
  }

  // Two groups of different drones and behaviors: each drone's group in drones.csv and fleet.csv, and
  // the per-group found counts of summary.csv and outcome.csv are the targets.csv finders' groups.
  void two_groups_report_per_group() {
    QTemporaryDir out;
    const QString dir = run(R"({"name": "two", "groups": [
        {"name": "surveyors", "drones": 4, "drone": "large", "behavior": "pheromone_avoidance", "spawn": {"point": [100, 100]}},
        {"name": "inspectors", "drones": 6, "drone": "small", "behavior": {"name": "random_walk"}}],
      "map": {"name": "forest", "params": {"size": 500}}, "targets": {"count": 300}, "time": 60})",
                            out);
    const auto fleet = rows_of(dir + "/fleet.csv");
    QCOMPARE(fleet.size(), std::size_t(11));
    const std::size_t group = column(fleet, "group");
    for (std::size_t i = 1; i <= 10; ++i) QCOMPARE(fleet[i][group], std::string(i <= 4 ? "surveyors" : "inspectors"));
    // Found per group, from targets.csv's finders.
    const auto targets = rows_of(dir + "/targets.csv");
    std::map<std::string, int> found;
    for (std::size_t t = 1; t < targets.size(); ++t)
      if (const std::string& by = targets[t][column(targets, "found_by")]; !by.empty()) ++found[fleet[std::stoul(by) + 1][group]];
    QVERIFY2(found["surveyors"] > 0 && found["inspectors"] > 0, "both groups find trees");
    const auto outcome = rows_of(dir + "/outcome.csv");
    QCOMPARE(std::stoi(outcome[1][column(outcome, "surveyors.found")]), found["surveyors"]);
    QCOMPARE(std::stoi(outcome[1][column(outcome, "inspectors.found")]), found["inspectors"]);
    QCOMPARE(std::stoi(outcome[1][column(outcome, "surveyors.alive")]), 4);
    QCOMPARE(std::stoi(outcome[1][column(outcome, "alive")]), 10);
    const auto summary = rows_of(dir + "/summary.csv");
    const auto& last = summary.back();
    QCOMPARE(std::stoi(last[column(summary, "surveyors.found")]) + std::stoi(last[column(summary, "inspectors.found")]),
             std::stoi(last[column(summary, "targets_found")]));
    // drones.csv: each row's group, the large drones first.
    const auto drones = rows_of(dir + "/drones.csv");
    QCOMPARE(drones[0].back(), std::string("energy_used_Wh"));
    QCOMPARE(drones[1][column(drones, "group")], std::string("surveyors"));
    QCOMPARE(drones[10][column(drones, "group")], std::string("inspectors"));
    // The resolved test keeps the groups: rerunning config.json gives the same data.
    QTemporaryDir again;
    const TestSpec rerun = load_tests((dir + "/config.json").toStdString(), *host_)[0];
    QCOMPARE(rerun.groups.size(), std::size_t(2));
    RunOptions options;
    options.out = again.path().toStdString();
    run_test(rerun, *host_, options);
    QCOMPARE(read_file(again.path() + "/two/drones.csv"), read_file(dir + "/drones.csv"));
  }

  // A timed change of one group's behavior parameter changes that group's flight only. The groups fly
  // apart (no contact between them), so the other group's rows are byte for byte the same.
  void a_groups_change_touches_only_that_group() {
    auto test = [](const std::string& changes) {
      return R"({"name": "g", "groups": [
          {"name": "a", "drones": 5, "behavior": "random_walk", "spawn": {"point": [200, 200], "radius": 20}},
          {"name": "b", "drones": 5, "behavior": "random_walk", "spawn": {"point": [1800, 1800], "radius": 20}}],
        "map": {"name": "empty", "params": {"size": 2000}}, "time": 30, "changes": )" + changes + "}";
    };
    QTemporaryDir plain, changed;
    const auto before = rows_of(run(test("[]"), plain) + "/drones.csv");
    const auto after = rows_of(run(test(R"([{"time": 10, "set": {"groups.a.behavior.params.max_duration": 3}}])"), changed) + "/drones.csv");
    QCOMPARE(before.size(), after.size());
    const std::size_t group = column(before, "group");
    int differ_a = 0, differ_b = 0;
    for (std::size_t r = 1; r < before.size(); ++r) (before[r][group] == "a" ? differ_a : differ_b) += before[r] != after[r];
    QVERIFY2(differ_a > 0, "group a flies differently after its change");
    QCOMPARE(differ_b, 0);
  }

  // Failure times come from the seed, not the behavior: every behavior of a repeat loses the same
  // drones at the same times.
  void failure_times_are_paired_across_behaviors() {
    std::map<std::string, std::vector<std::pair<std::string, std::string>>> failed;  // behavior → (id, since)
    for (const char* behavior : {"flocking", "random_walk", "pheromone_avoidance"}) {
      QTemporaryDir out;
      std::string json = R"({"name": "f", "behavior": "B", "drones": 20, "failures": {"drone_mtbf": 200, "camera_mtbf": 300},
                             "map": {"name": "forest", "params": {"size": 500}}, "targets": {"count": 100}, "time": 60})";
      json.replace(json.find("\"B\"") + 1, 1, behavior);
      const QString dir = run(json, out);
      const auto fleet = rows_of(dir + "/fleet.csv");
      for (std::size_t i = 1; i < fleet.size(); ++i)
        if (fleet[i][column(fleet, "status")] == "failed") failed[behavior].emplace_back(fleet[i][0], fleet[i][column(fleet, "since")]);
    }
    QVERIFY2(failed["flocking"].size() >= 2, "an MTBF of 200 s fails a few of 20 drones in 60 s");
    QCOMPARE(failed["random_walk"], failed["flocking"]);
    QCOMPARE(failed["pheromone_avoidance"], failed["flocking"]);
  }

  // The exponential clock: over many drones the share failed by time t is 1 − exp(−t / MTBF).
  void failures_follow_the_exponential_law() {
    SimulationSetup s = open_field(2000, std::make_shared<Counter>());
    s.failures.drone_mtbf = 100;
    s.dt = 1;
    s.groups[0].drone.max_speed = 1;
    Simulation sim(s);
    sim.run_steps(50);
    const double expected = 2000 * (1 - std::exp(-50.0 / 100));  // 787
    const double failed = 2000.0 - static_cast<double>(sim.flying_count());
    QVERIFY2(std::abs(failed - expected) < 4 * std::sqrt(expected * (1 - expected / 2000)),
             qPrintable(QString("%1 failed, %2 expected").arg(failed).arg(expected)));
  }

  // Survivors keep their memory when others fail and when the count drops (no reset), and new drones
  // start fresh.
  void memory_survives_failures_and_a_lower_count() {
    auto counter = std::make_shared<Counter>();
    Simulation sim(open_field(10, counter));
    sim.run_steps(20);
    sim.fail(7);
    sim.fail_fraction(0.2);
    sim.run_steps(5);
    sim.set_drone_count(4);
    sim.run_steps(5);
    sim.set_drone_count(6);
    sim.run_steps(5);
    QCOMPARE(counter->inspect(0), std::string("35"));  // every step since the start
    QCOMPARE(counter->inspect(7), std::string("20"));  // failed at 20: decides no more
    QCOMPARE(sim.drone_status()[7], DroneStatus::removed);  // the count's drop took the highest ids, failed or not
    QCOMPARE(counter->inspect(10), std::string("5"));  // a new id, fresh memory
    QCOMPARE(sim.drone_count(), std::size_t(12));
  }

  // Energy drawn over a scripted flight is the power model's integral: the sum of P(speed) · dt over
  // the steps, at each step's speed.
  void energy_is_the_power_models_integral() {
    SimulationSetup s = open_field(1, std::make_shared<Counter>(Vec2{6, 0}));
    s.groups[0].drone.battery_capacity = 1000;
    Simulation sim(s);
    double expected = 0;
    for (int k = 0; k < 200; ++k) {
      sim.step();
      expected += flight_power(s.groups[0].drone, sim.drone_velocities()[0].length()) * s.dt;
    }
    QVERIFY(std::abs(sim.energy_used(0) - expected) <= 1e-9 * expected);
    // Hover (the model's P0 + Pi) and the speed term, against the formula written out.
    const DroneConfig& d = s.groups[0].drone;
    QCOMPARE(flight_power(d, 0), d.blade_power + d.induced_power);
    const double v = 6, v0 = d.induced_velocity;
    const double by_hand = d.blade_power * (1 + 3 * v * v / (d.tip_speed * d.tip_speed)) +
                           d.induced_power * std::sqrt(std::sqrt(1 + std::pow(v, 4) / (4 * std::pow(v0, 4))) - v * v / (2 * v0 * v0)) +
                           d.parasite_drag * v * v * v;
    QVERIFY(std::abs(flight_power(d, v) - by_hand) < 1e-9);
  }

  // An empty battery lands the drone at the step it runs out: it stops there, for good.
  void an_empty_battery_lands_the_drone_at_that_step() {
    SimulationSetup s = open_field(1, std::make_shared<Counter>(Vec2{5, 0}));
    s.groups[0].drone.battery_capacity = 0.5;  // Wh: 1800 J, about 10 s at ~170 W
    Simulation sim(s);
    double drawn = 0;
    int landed_at = -1;
    for (int k = 1; k <= 200 && landed_at < 0; ++k) {
      const double before = drawn;
      sim.step();
      if (sim.drone_status()[0] == DroneStatus::landed) landed_at = k, drawn = before;
      else drawn = sim.energy_used(0);
    }
    QVERIFY(landed_at > 0);
    QVERIFY2(drawn < 1800 && std::abs(sim.energy_used(0) - 1800) < 1e-9, "lands in the step its battery runs out, having drawn all of it");
    QCOMPARE(sim.status_time(0), sim.time());
    const Vec2 there = sim.drone_positions()[0];
    sim.run_steps(20);
    QCOMPARE(sim.drone_positions()[0], there);
    QCOMPARE(sim.flying_count(), std::size_t(0));
  }

  // A battery gives what it holds and no more, whatever the step: the step that empties it is charged
  // only the energy left (at dt 1 s a 0.05 Wh battery was charged a whole step: 187 %).
  void energy_used_never_exceeds_the_capacity() {
    for (const double dt : {0.01, 0.1, 0.25, 1.0}) {
      SimulationSetup s = open_field(1, std::make_shared<Counter>(Vec2{0.9, 0}));
      s.dt = dt;
      s.groups[0].drone.max_speed = 0.9;  // under a radius a step at dt 1 s
      s.groups[0].drone.battery_capacity = 0.05;  // Wh: 180 J, about one second at ~170 W
      Simulation sim(s);
      for (int k = 0; k < 1000 && sim.flying_count() > 0; ++k) sim.step();
      QCOMPARE(sim.drone_status()[0], DroneStatus::landed);
      const double capacity = 0.05 * 3600;
      QVERIFY2(sim.energy_used(0) <= capacity, qPrintable(QString("dt %1: %2 J used of %3 J").arg(dt).arg(sim.energy_used(0)).arg(capacity)));
      QVERIFY2(sim.energy_used(0) >= capacity * (1 - 1e-12), qPrintable(QString("dt %1: %2 J used").arg(dt).arg(sim.energy_used(0))));
    }
  }

  // A landed drone is no one's neighbour and finds nothing; a camera failure keeps it flying, blind.
  void a_camera_failure_flies_on_blind() {
    QTemporaryDir out;
    const QString dir = run(R"({"name": "blind", "behavior": "random_walk", "drones": 3,
        "map": {"name": "forest", "params": {"size": 300}}, "targets": {"count": 200}, "time": 60,
        "changes": [{"time": 0, "set": {"fail.camera": 1}}]})",
                            out);
    const auto targets = rows_of(dir + "/targets.csv");
    for (std::size_t t = 1; t < targets.size(); ++t) QVERIFY(targets[t][column(targets, "found_by")] != "1");
    const auto fleet = rows_of(dir + "/fleet.csv");
    QCOMPARE(fleet[2][column(fleet, "status")], std::string("camera_failed"));
    const auto drones = rows_of(dir + "/drones.csv");
    QVERIFY(drones.back()[column(drones, "status")] != "failed");
  }
};

QTEST_GUILESS_MAIN(TestFleet)
#include "test_fleet.moc"
