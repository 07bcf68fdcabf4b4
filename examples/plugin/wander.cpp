// wander.cpp: a behavior, the whole of it. Each drone flies a random heading, turns to a new one every
// `turn_interval` seconds, and keeps away from obstacles.
#include <salsa/sdk.hpp>

struct Heading {
  double angle = 0, since = 1e9;  // since: seconds on this heading
};

class Wander final : public salsa::BehaviorWithMemory<Heading> {
  salsa::Param turn_interval{this, "turn_interval", 2.0, 0.1, 30.0, "s", "time between heading changes"};
  salsa::Param avoidance{this, "avoidance", 2.0, 0.0, 10.0, "", "weight of obstacle avoidance"};

 public:
  salsa::Vec2 decide(const salsa::Perception& me, Heading& h, salsa::Rng& rng) override {
    if ((h.since += me.dt) > turn_interval) h = {rng.angle(), 0};
    return steer_towards(me, full_speed(me, h.angle)) + avoidance * avoid_obstacles(me);
  }
};
SALSA_BEHAVIOR(Wander, "wander", "Random heading changes, avoids obstacles")
