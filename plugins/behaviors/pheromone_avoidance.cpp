// Pheromone avoidance: the class is published in the SDK (salsa/behaviors/pheromone_avoidance.hpp) so
// that a plugin can derive from it; this file registers it.
#include <salsa/behaviors/pheromone_avoidance.hpp>
#include <salsa/sdk.hpp>

SALSA_BEHAVIOR(salsa::behaviors::PheromoneAvoidance, "pheromone_avoidance", "Steers towards the least recently visited ground")
