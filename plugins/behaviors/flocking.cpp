// Reynolds boids as in the SALSA paper (workload table1): alignment, separation, cohesion and
// obstacle avoidance, each a steering term clamped to max force, summed with weights.
#include <salsa/sdk.hpp>

namespace {

class Flocking final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    return {
        {"separation_distance", 250.0, 0.0, 1000.0, "m", "neighbours closer than this push the drone away"},
        {"alignment_weight", 1.6, 0.0, 10.0, "", "weight of matching the neighbours' mean velocity"},
        {"cohesion_weight", 1.0, 0.0, 10.0, "", "weight of flying towards the neighbours' centre"},
        {"separation_weight", 3.0, 0.0, 10.0, "", "weight of keeping the separation distance"},
        {"obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"},
    };
  }

  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    const auto boids = salsa::boid_terms(me, separation_distance_);
    return alignment_weight_ * boids.alignment + separation_weight_ * boids.separation +
           cohesion_weight_ * boids.cohesion + obstacle_weight_ * salsa::avoid_obstacles(me);
  }

  salsa::Senses senses() const override { return {.neighbours = true, .targets = false}; }

 protected:
  void configure() override {  // decide is hot: no name lookups there
    separation_distance_ = param("separation_distance");
    alignment_weight_ = param("alignment_weight");
    cohesion_weight_ = param("cohesion_weight");
    separation_weight_ = param("separation_weight");
    obstacle_weight_ = param("obstacle_avoidance_weight");
  }

 private:
  double separation_distance_ = 0, alignment_weight_ = 0, cohesion_weight_ = 0, separation_weight_ = 0,
         obstacle_weight_ = 0;
};

}  // namespace

SALSA_BEHAVIOR(Flocking, "flocking", "Reynolds boids: alignment, separation, cohesion, obstacle avoidance")
