// flocking_plus.cpp: a built-in behavior extended, not copied. salsa's flocking (its class comes with
// the SDK) plus one more steering term, migration: every drone also steers towards a goal point, so
// the flock travels there together. Only the hook `combine` is overridden; the rest is the built-in's.
#include <salsa/behaviors/flocking.hpp>
#include <salsa/sdk.hpp>

class FlockingPlus final : public salsa::behaviors::Flocking {
  salsa::Param migration_weight{this, "migration_weight", 1.0, 0.0, 10.0, "", "weight of flying towards the goal"};
  salsa::Param goal_x{this, "goal_x", 0.0, -1e6, 1e6, "m", "the goal's x"};
  salsa::Param goal_y{this, "goal_y", 0.0, -1e6, 1e6, "m", "the goal's y"};

 protected:
  salsa::Vec2 combine(const salsa::Perception& me, const salsa::BoidTerms& boids, salsa::Rng& rng) override {
    return Flocking::combine(me, boids, rng) + migration_weight * salsa::seek(me, {goal_x, goal_y});
  }
};
SALSA_BEHAVIOR(FlockingPlus, "flocking_plus", "Flocking plus migration towards a goal point")
