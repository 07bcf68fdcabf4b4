// Return to base around any behavior (drone.return_to_base): what a battery study relies on — every
// built-in behavior's drones come home before they run flat, charge and fly out again; a drone turns
// home when its energy left is the way home's need (the documented formula) plus the reserve, earlier
// into a headwind; its behavior is not asked while away and keeps its memory; off changes nothing.
#include <QtTest>

#include <cmath>
#include <map>
#include <set>

#include "common.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/run/runner.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

/// Flies at a fixed velocity through the air and counts its own decisions in its memory.
class Away final : public BehaviorWithMemory<int> {
 public:
  explicit Away(Vec2 air) : air_(air) {}
  Vec2 decide(const Perception& me, int& decisions, Rng&) override {
    ++decisions;
    return air_ - me.air_velocity;
  }
  std::string inspect(std::uint32_t id) const override { return id < memory().size() ? std::to_string(memory()[id]) : ""; }

 private:
  Vec2 air_;
};

constexpr double reserve_wh = 0.1;

/// One drone from a base at (100, 1000) on an empty 2 km field, flying east at 5 m/s through the air,
/// with a 1 Wh battery, return to base on (reserve 0.1 Wh) and a 1 kW charger.
SimulationSetup eastward(Vec2 wind) {
  SimulationSetup s;
  s.map.bounds = {{0, 0}, {2000, 2000}};
  s.map.spawn = {100, 1000};
  s.groups[0].drones = 1;
  s.groups[0].behavior = std::make_shared<Away>(Vec2{5, 0});
  DroneConfig& d = s.groups[0].drone;
  d.battery_capacity = 1;
  d.charge_power = 1000;
  d.return_to_base = 1;
  d.return_reserve = reserve_wh;
  s.wind.velocity = wind;
  s.dt = 0.05;
  return s;
}

/// A drone's state as the outputs show it, step by step.
struct Trace {
  std::vector<double> time, charge, need, charged;
  std::vector<Errand> errand;
  std::vector<Vec2> position, velocity;
  std::vector<int> decisions;
};

double value(const Simulation& sim, const char* name, std::uint32_t id) {
  const StateColumn c = sim.column(name);
  if (!c.data) qFatal("no column %s", name);
  return static_cast<const double*>(c.data)[id];
}

Trace fly(Simulation& sim, double seconds) {
  Trace t;
  while (sim.time() < seconds - 1e-9) {
    sim.step();
    t.time.push_back(sim.time());
    t.charge.push_back(sim.battery_left(0));
    t.need.push_back(value(sim, "energy_home", 0));
    t.charged.push_back(sim.charging_time(0));
    t.errand.push_back(sim.errand(0));
    t.position.push_back(sim.drone_positions()[0]);
    t.velocity.push_back(sim.drone_velocities()[0]);
    t.decisions.push_back(std::stoi(sim.behavior().inspect(0)));
  }
  return t;
}

/// docs/test-format.md's need, written out: turn onto the way home, cruise, brake (a = max_force / 2dt).
double documented_need(const DroneConfig& d, Vec2 to_base, Vec2 v, double headwind, double dt) {
  const double full = flight_power(d, d.max_speed), most = std::max(flight_power(d, 0), full);
  const double a = d.max_force / (2 * dt), distance = to_base.length();
  const double g = d.max_speed - headwind;  // the wind lies along the way home
  const double top = std::min(g, std::sqrt(2 * a * distance));
  const double turn = (to_base / distance * top - v).length() / (d.max_force / dt);
  const double cruise = std::max(0.0, distance - top * top / (2 * a)) / g;
  return (turn + top / a) * most + cruise * full;
}

std::size_t first(const Trace& t, Errand e, std::size_t from = 0) {
  for (std::size_t k = from; k < t.errand.size(); ++k)
    if (t.errand[k] == e) return k;
  return t.errand.size();
}


}  // namespace

class TestReturnToBase : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

  QString run(const std::string& json, QTemporaryDir& out, std::vector<std::string> columns = {}) {
    const TestSpec test = parse_test(json, "rtb.json", *host_);
    RunOptions options;
    options.out = out.path().toStdString();
    options.threads = 1;
    options.drone_columns = std::move(columns);
    run_test(test, *host_, options);
    return out.path() + "/" + q(test.name);
  }

  static std::string survey(const std::string& behavior, int return_to_base) {
    return "{\"name\": \"rtb\", \"behavior\": \"" + behavior + "\", \"drones\": 8, \"drone\": {\"battery_capacity\": 1.5, " +
           "\"charge_power\": 2000, \"return_to_base\": " + std::to_string(return_to_base) +
           ", \"return_reserve\": 0.15, \"resume_charge\": 1}, \"map\": {\"name\": \"forest\", \"params\": {\"size\": 300}}, " +
           "\"targets\": {\"count\": 100}, \"time\": 150, \"log_interval\": 0.5, \"seed\": 3}";
  }

 private Q_SLOTS:
  // Every built-in behavior with a battery too small for the test (without return to base drones land
  // empty): every drone comes home, charges and flies out again to its behavior; none lands, no battery
  // goes below zero, and the outputs carry the errands and the time charged.
  void every_builtin_behavior_comes_home() {
    for (const char* behavior :
         {"random_walk", "flocking", "pheromone_avoidance", "dynamic_space_partitioning", "dynamic_space_partitioning_paper"}) {
      QTemporaryDir off_dir, on_dir;
      const auto off = rows_of(run(survey(behavior, 0), off_dir) + "/fleet.csv");
      int landed = 0;
      for (std::size_t r = 1; r < off.size(); ++r) landed += off[r][column(off, "status")] == "landed";
      QVERIFY2(landed > 0, behavior);  // the battery is too small for the test

      const QString dir = run(survey(behavior, 1), on_dir, {"battery_left", "errand"});
      const auto drones = rows_of(dir + "/drones.csv");
      const std::size_t id = column(drones, "id"), status = column(drones, "status"), battery = column(drones, "battery_left");
      const std::size_t charging = column(drones, "charging_s"), errand = column(drones, "errand");
      std::map<std::string, std::vector<std::string>> seen;  // per drone, its statuses in time order
      for (std::size_t r = 1; r < drones.size(); ++r) {
        const auto& row = drones[r];
        QVERIFY2(std::stod(row[battery]) > 0, (std::string(behavior) + ": an empty battery at " + row[0]).c_str());
        auto& s = seen[row[id]];
        if (s.empty() || s.back() != row[status]) s.push_back(row[status]);
        // The status column and the errand column say the same.
        static const std::map<std::string, std::string> errands{{"flying", "0"}, {"returning", "1"}, {"charging", "2"}, {"outbound", "3"}};
        QVERIFY2(errands.contains(row[status]), (std::string(behavior) + ": status " + row[status]).c_str());
        if (row[0] != "0.0000") QCOMPARE(row[errand], errands.at(row[status]));  // kept from the first step on
        if (row[status] == "charging") QVERIFY(std::stod(row[charging]) > 0);
      }
      QCOMPARE(seen.size(), std::size_t(8));
      for (const auto& [drone, statuses] : seen) {
        // flying, returning, charging, outbound, flying again (and maybe more trips).
        const std::string trip = std::string(behavior) + ": drone " + drone + " went";
        auto at = [&](const char* s, std::size_t from) { return std::find(statuses.begin() + from, statuses.end(), s) - statuses.begin(); };
        const std::size_t r = at("returning", 0), c = at("charging", r), o = at("outbound", c), f = at("flying", o);
        QVERIFY2(f < statuses.size(), (trip + " " + std::to_string(statuses.size()) + " statuses without a whole trip").c_str());
      }
      // fleet.csv's time charged per drone adds up to outcome.csv's and to the last summary row's.
      const auto fleet = rows_of(dir + "/fleet.csv");
      double total = 0;
      for (std::size_t r = 1; r < fleet.size(); ++r) {
        QVERIFY(fleet[r][column(fleet, "status")] != "landed");
        const double s = std::stod(fleet[r][column(fleet, "charging_s")]);
        QVERIFY2(s > 0, behavior);
        total += s;
      }
      const auto outcome = rows_of(dir + "/outcome.csv");
      QVERIFY(std::abs(std::stod(outcome[1][column(outcome, "charging_s")]) - total) < 1e-3);
      QCOMPARE(std::stoi(outcome[1][column(outcome, "alive")]), 8);
      const auto summary = rows_of(dir + "/summary.csv");
      QCOMPARE(summary.back()[column(summary, "charging_s")], outcome[1][column(outcome, "charging_s")]);
    }
  }

  // A drone turns home at the first step its energy left is at most the documented need + reserve:
  // the step before it was above. Its behavior is not asked while it is away and finds its memory as
  // it left it; it arrives with at least the reserve, charges to full, flies back to where it left off
  // and its behavior flies it again.
  void turns_home_at_the_documented_need() {
    Simulation sim(eastward({}));
    const Trace t = fly(sim, 120);
    const DroneConfig& d = sim.drone_config();
    const double reserve = reserve_wh * 3600, base_x = 100;
    const std::size_t k = first(t, Errand::returning);
    QVERIFY2(k > 0 && k < t.time.size(), "the drone turns home");
    QVERIFY(t.charge[k] <= t.need[k] + reserve);
    QVERIFY(t.charge[k - 1] > t.need[k - 1] + reserve);
    const Vec2 to_base = sim.spawn_point() - t.position[k];
    QVERIFY(std::abs(sim.spawn_point().x - base_x) < 1e-9);
    QVERIFY(std::abs(t.need[k] - documented_need(d, to_base, t.velocity[k], 0, 0.05)) < 1e-6 * t.need[k]);
    // Within one step's energy of the threshold.
    QVERIFY(t.need[k] + reserve - t.charge[k] <= flight_power(d, 5) * 0.05 + std::abs(t.need[k] - t.need[k - 1]) + 1e-9);

    const std::size_t c = first(t, Errand::charging, k), o = first(t, Errand::outbound, c), back = first(t, Errand::none, o);
    QVERIFY2(back < t.time.size(), "home, charged and back out within 120 s");
    QVERIFY2(t.charge[c] >= reserve, "arrives with the reserve");
    QVERIFY(distance(t.position[c], sim.spawn_point()) <= d.charge_radius);
    QCOMPARE(t.charge[o], d.battery_capacity * 3600);  // resume_charge 1: full
    // Step k's decide was its behavior's (the turn comes after the step's flight); from then on, up to the
    // step it is back, the core's.
    for (std::size_t s = k; s <= back; ++s) QCOMPARE(t.decisions[s], t.decisions[k]);
    const std::size_t again = first(t, Errand::returning, back);  // the next trip home, if any
    QCOMPARE(t.decisions[again - 1], t.decisions[k] + static_cast<int>(again - 1 - back));  // its memory, counting on
    QVERIFY(distance(t.position[back], t.position[k]) <= d.radius + 1);  // where it left off
    QVERIFY(std::abs(t.charged[o] - static_cast<double>(o - c + 1) * 0.05) < 1e-9);  // every step on the base
    QCOMPARE(t.charged[o], t.charged[back]);
    for (double e : t.charge) QVERIFY(e > 0);
  }

  // A headwind on the way home (the wind blowing away from the base): the way home takes longer, so
  // the drone turns earlier and with more energy left, by the documented need at the headwind's ground
  // speed; it still gets home with its reserve.
  void a_headwind_home_turns_earlier() {
    Simulation calm(eastward({}));
    Simulation windy(eastward({3, 0}));
    const Trace a = fly(calm, 60), b = fly(windy, 60);
    const std::size_t ka = first(a, Errand::returning), kb = first(b, Errand::returning);
    QVERIFY(ka < a.time.size() && kb < b.time.size());
    QVERIFY2(kb < ka, "turns earlier into a headwind");
    QVERIFY(b.charge[kb] > a.charge[ka]);
    const double reserve = reserve_wh * 3600;
    QVERIFY(b.charge[kb] <= b.need[kb] + reserve && b.charge[kb - 1] > b.need[kb - 1] + reserve);
    const Vec2 to_base = windy.spawn_point() - b.position[kb];
    QVERIFY(std::abs(b.need[kb] - documented_need(windy.drone_config(), to_base, b.velocity[kb], 3, 0.05)) < 1e-6 * b.need[kb]);
    const std::size_t c = first(b, Errand::charging, kb);
    QVERIFY2(c < b.time.size(), "home against the wind");
    QVERIFY(b.charge[c] >= reserve);
  }

  // Off (the default, or 0 with the other two set) writes the same bytes as a test without the fields.
  void off_gives_the_same_bytes() {
    const std::string common = R"("behavior": "random_walk", "drones": 6, "map": {"name": "forest", "params": {"size": 300}},
        "targets": {"count": 50}, "time": 40, "seed": 5)";
    QTemporaryDir a, b;
    const QString plain = run(R"({"name": "t", "drone": {"battery_capacity": 0.3, "charge_power": 100}, )" + common + "}", a);
    const QString off = run(R"({"name": "t", "drone": {"battery_capacity": 0.3, "charge_power": 100, "return_to_base": 0,
        "return_reserve": 0.2, "resume_charge": 0.5}, )" + common + "}", b);
    for (const char* file : {"summary.csv", "drones.csv", "targets.csv", "outcome.csv", "fleet.csv", "config.json"})
      QVERIFY2(read_file(plain + "/" + file) == read_file(off + "/" + file), file);
    QVERIFY(!read_file(off + "/fleet.csv").contains("charging_s"));
  }

  // On, config.json carries the three fields and reruns to the same data; a timed change turns it on
  // mid-test (the outputs then carry the time charged from the start).
  void written_and_changed() {
    QTemporaryDir out, again, changed;
    const QString dir = run(survey("random_walk", 1), out);
    const QByteArray config = read_file(dir + "/config.json");
    for (const char* key : {"\"return_to_base\": 1", "\"return_reserve\": 0.15", "\"resume_charge\": 1"}) QVERIFY2(config.contains(key), key);
    const TestSpec rerun = load_tests((dir + "/config.json").toStdString(), *host_)[0];
    RunOptions options;
    options.out = again.path().toStdString();
    options.threads = 1;
    run_test(rerun, *host_, options);
    QCOMPARE(read_file(again.path() + "/rtb/drones.csv"), read_file(dir + "/drones.csv"));

    std::string later = survey("random_walk", 0);
    later.insert(later.rfind('}'), R"(, "changes": [{"time": 10, "set": {"drone.return_to_base": 1}}])");
    const auto fleet = rows_of(run(later, changed) + "/fleet.csv");
    for (std::size_t r = 1; r < fleet.size(); ++r) {
      QVERIFY(fleet[r][column(fleet, "status")] != "landed");
      QVERIFY(std::stod(fleet[r][column(fleet, "charging_s")]) > 0);
    }
  }
};

QTEST_GUILESS_MAIN(TestReturnToBase)
#include "test_return_to_base.moc"
