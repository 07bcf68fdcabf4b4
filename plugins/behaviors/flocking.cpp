// Flocking: the class is published in the SDK (salsa/behaviors/flocking.hpp) so that a plugin can
// derive from it; this file registers it.
#include <salsa/behaviors/flocking.hpp>
#include <salsa/sdk.hpp>

SALSA_BEHAVIOR(salsa::behaviors::Flocking, "flocking", "Reynolds boids: alignment, separation, cohesion, obstacle avoidance")
