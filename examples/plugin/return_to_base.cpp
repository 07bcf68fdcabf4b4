// return_to_base.cpp: a behavior for drones with a battery. Each drone wanders (random headings, away
// from obstacles) while its battery is above `reserve`, then flies home to its group's base and stops
// there, where a base that charges (the drone's charge_power) fills it; above `resume` it flies out again.
// Without a battery model (battery_capacity 0) the battery reads 1 and the drones just wander.
#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <salsa/sdk.hpp>

struct Trip {
  bool home = false;                // flying home, or on the base
  double heading = 0, since = 1e9;  // since: seconds on this heading
  double battery = 1;               // as last seen, for inspect
};

class ReturnToBase final : public salsa::BehaviorWithMemory<Trip> {
  salsa::Param reserve{this, "reserve", 0.4, 0.0, 1.0, "", "battery fraction at which a drone turns home"};
  salsa::Param resume{this, "resume", 1.0, 0.0, 1.0, "", "battery fraction at which a charging drone flies out again"};
  salsa::Param turn_interval{this, "turn_interval", 5.0, 0.1, 60.0, "s", "time between heading changes"};
  salsa::Param avoidance{this, "avoidance", 4.0, 0.0, 10.0, "", "weight of obstacle avoidance"};

 public:
  void configure() override {
    if (resume <= reserve) throw std::invalid_argument("resume must be above reserve, or a charged drone turns straight home");
  }

  salsa::Vec2 decide(const salsa::Perception& me, Trip& t, salsa::Rng& rng) override {
    t.battery = me.battery;
    const double to_base = salsa::distance(me.position, me.base);
    if (!t.home && me.battery <= reserve) t.home = true;
    else if (t.home && me.battery >= resume) t.home = false, t.since = 1e9;  // only charging raises the battery
    if (!t.home) {
      if ((t.since += me.dt) > turn_interval) t.heading = rng.angle(), t.since = 0;
      return salsa::steer_towards(me, salsa::full_speed(me, t.heading)) + avoidance * salsa::avoid_near_obstacles(me);
    }
    // Home: at most full speed, distance / 2 s near the end, so that it comes to rest on the base (the
    // core charges a drone slower than 1 m/s within charge_radius of it) and holds still there.
    const salsa::Vec2 arrive = (me.base - me.position).with_length(std::min(me.max_speed, to_base / 2));
    const double clear = std::min(1.0, to_base / 20);  // no avoidance on the base itself, which is free space
    return salsa::steer_towards(me, arrive) + clear * avoidance * salsa::avoid_near_obstacles(me);
  }

  salsa::Senses senses() const override { return {.neighbours = false, .targets = false}; }  // obstacles only

  std::string inspect(std::uint32_t id) const override {
    if (id >= memory().size()) return {};
    char text[64];
    std::snprintf(text, sizeof text, "%s, battery %.1f%%", memory()[id].home ? "home" : "out", 100 * memory()[id].battery);
    return text;
  }
};
SALSA_BEHAVIOR(ReturnToBase, "return_to_base", "Wanders, flies home at a battery reserve, charges, flies again")
