// The flocking model of the agent-based-modelling frameworks' comparison (JuliaDynamics/
// ABMFrameworksComparison, Flocking/DECLARATION.md): its update rule, parameter names and defaults, so
// salsa runs the same model the frameworks time. A bird's velocity there is a unit vector and it moves
// `speed` per step; here the drone flies v̂ × speed / dt m/s, so one salsa step is one of theirs
// (dt = 1 s: speed in m/s). docs/behaviors.md says what differs (walls, simultaneous update).
#include <salsa/sdk.hpp>

#include <cmath>

namespace {

class AbmFlocking final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng& rng) override {
    using salsa::Vec2;
    const double to_unit = me.dt / speed;  // m/s → their unit velocity
    Vec2 vel = me.velocity * to_unit;
    // Their birds start with a velocity uniform in [-1, 1]²; a salsa drone starts at rest.
    if (vel.is_zero()) vel = {rng.uniform(-1, 1), rng.uniform(-1, 1)};
    Vec2 cohere, separate, match;
    int n = 0;
    for (const auto& other : me.neighbours) {
      if (other.distance > visual_distance) continue;
      ++n;
      const Vec2 heading = other.position - me.position;
      cohere += heading;
      if (other.distance < separation) separate -= heading;
      match += other.velocity * to_unit;
    }
    const double count = std::max(n, 1);
    Vec2 next = (vel + cohere / count * cohere_factor + separate / count * separate_factor + match / count * match_factor) / 2;
    if (next.is_zero()) return -me.velocity;  // no direction to normalise (theirs would be NaN): stay
    next = next / next.length();
    return next * (speed / me.dt) - me.velocity;  // the core adds the change to the velocity
  }

  salsa::Senses senses() const override { return {.neighbours = true, .targets = false}; }

 private:
  // Lengths are metres here, their space units; the drone's detection_range must reach visual_distance
  // and its max_speed must allow speed / dt.
  salsa::Param speed{this, "speed", 1.0, 0.001, 1000.0, "m/step", "distance a bird moves each step"};
  salsa::Param cohere_factor{this, "cohere_factor", 0.03, 0.0, 10.0, "", "weight of the mean offset to the neighbours"};
  salsa::Param separation{this, "separation", 1.0, 0.0, 1000.0, "m", "neighbours closer than this push the bird away"};
  salsa::Param separate_factor{this, "separate_factor", 0.015, 0.0, 10.0, "", "weight of the push away from close neighbours"};
  salsa::Param match_factor{this, "match_factor", 0.05, 0.0, 10.0, "", "weight of the neighbours' mean velocity"};
  salsa::Param visual_distance{this, "visual_distance", 5.0, 0.0, 100000.0, "m", "birds within this distance are neighbours"};
};

}  // namespace

SALSA_BEHAVIOR(AbmFlocking, "abm_flocking",
               "The ABM frameworks' flocking model (ABMFrameworksComparison): cohere, separate, match, unit velocity")
