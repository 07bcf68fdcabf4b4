// Reynolds boids as in the SALSA paper (workload table1): alignment, separation, cohesion and
// obstacle avoidance, each a steering term clamped to max force, summed with weights.
#include <salsa/sdk.hpp>

namespace {

class Flocking final : public salsa::Behavior {
  using Param = salsa::Param;  // each parameter once: its declaration, and its value in decide
  Param separation_distance{this, "separation_distance", 250.0, 0.0, 1000.0, "m", "neighbours closer than this push the drone away"};
  Param alignment_weight{this, "alignment_weight", 1.6, 0.0, 10.0, "", "weight of matching the neighbours' mean velocity"};
  Param cohesion_weight{this, "cohesion_weight", 1.0, 0.0, 10.0, "", "weight of flying towards the neighbours' centre"};
  Param separation_weight{this, "separation_weight", 3.0, 0.0, 10.0, "", "weight of keeping the separation distance"};
  Param obstacle_weight{this, "obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"};

 public:
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    const auto boids = salsa::boid_terms(me, separation_distance);
    return alignment_weight * boids.alignment + separation_weight * boids.separation +
           cohesion_weight * boids.cohesion + obstacle_weight * salsa::avoid_obstacles(me);
  }

  salsa::Senses senses() const override { return {.neighbours = true, .targets = false}; }
};

}  // namespace

SALSA_BEHAVIOR(Flocking, "flocking", "Reynolds boids: alignment, separation, cohesion, obstacle avoidance")
