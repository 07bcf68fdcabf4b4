#pragma once
// Reynolds boids as in the SALSA paper (workload table1): alignment, separation, cohesion and
// obstacle avoidance, each a steering term clamped to max force, summed with weights. Every neighbour
// counts alike, whatever its group (the paper's definition); a derived class may weigh groups apart.
// Derive to add a term or change the sum (docs/plugins.md).
#include "salsa/behavior.hpp"

namespace salsa::behaviors {

class Flocking : public Behavior {
 public:
  Vec2 decide(const Perception& me, Rng& rng) override { return combine(me, boid_terms(me, separation_distance), rng); }

  Senses senses() const override { return {.neighbours = true, .targets = false}; }

 protected:
  /// The steering from the three boid terms (unweighted, each at most max force): their weighted sum
  /// plus obstacle avoidance. Override to add a term: `return Flocking::combine(me, boids, rng) + w * term;`.
  virtual Vec2 combine(const Perception& me, const BoidTerms& boids, Rng& rng) {
    (void)rng;
    return alignment_weight * boids.alignment + separation_weight * boids.separation +
           cohesion_weight * boids.cohesion + obstacle_weight * avoid_obstacles(me);
  }

  Param separation_distance{this, "separation_distance", 250.0, 0.0, 1000.0, "m", "neighbours closer than this push the drone away"};
  Param alignment_weight{this, "alignment_weight", 1.6, 0.0, 10.0, "", "weight of matching the neighbours' mean velocity"};
  Param cohesion_weight{this, "cohesion_weight", 1.0, 0.0, 10.0, "", "weight of flying towards the neighbours' centre"};
  Param separation_weight{this, "separation_weight", 3.0, 0.0, 10.0, "", "weight of keeping the separation distance"};
  Param obstacle_weight{this, "obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"};
};

}  // namespace salsa::behaviors
