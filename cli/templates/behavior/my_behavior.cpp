// my_behavior: a salsa behavior. Each drone keeps a heading of its own that drifts at random, and steers
// away from drones too close and from obstacles. decide() runs once per drone per step, possibly in
// parallel: it writes only its drone's memory and draws only from the rng it is given.
// The whole contract: plugins.md (installed in /usr/share/doc/salsa/).
#include <salsa/sdk.hpp>

namespace {

struct MyBehaviorMemory {  // per-drone memory, one slot per drone, owned by the core
  double angle = 0;       // rad: the heading
  bool chosen = false;
};

class MyBehavior final : public salsa::BehaviorWithMemory<MyBehaviorMemory> {
  // Each parameter once: name, default, min, max, unit, meaning (the GUI's sliders, the checks of a
  // test's JSON, sweeps). In decide() it is a plain double holding the current value.
  salsa::Param turn_rate{this, "turn_rate", 0.5, 0.0, 10.0, "rad/s", "how fast the heading drifts at random"};
  salsa::Param separation{this, "separation", 10.0, 0.0, 200.0, "m", "fly away from drones closer than this"};
  salsa::Param avoidance{this, "avoidance", 2.0, 0.0, 10.0, "", "weight of obstacle avoidance"};

 public:
  salsa::Vec2 decide(const salsa::Perception& me, MyBehaviorMemory& h, salsa::Rng& rng) override {
    if (!h.chosen) h = {rng.angle(), true};
    h.angle += rng.uniform(-1.0, 1.0) * turn_rate * me.dt;
    // Steering terms, each at most max force; the core adds the sum to the velocity.
    return salsa::steer_towards(me, salsa::full_speed(me, h.angle)) +
           salsa::avoid_drones(me, separation) + avoidance * salsa::avoid_obstacles(me);
  }
  // decide() never looks at the targets in view: the core need not gather them.
  salsa::Senses senses() const override { return {.neighbours = true, .targets = false}; }
};

}  // namespace

SALSA_BEHAVIOR(MyBehavior, "my_behavior", "Own heading drifting at random, avoids drones and obstacles")
