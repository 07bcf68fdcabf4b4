// Random walk: the class is published in the SDK (salsa/behaviors/random_walk.hpp) so that a plugin
// can derive from it; this file registers it.
#include <salsa/behaviors/random_walk.hpp>
#include <salsa/sdk.hpp>

SALSA_BEHAVIOR(salsa::behaviors::RandomWalk, "random_walk", "Random headings for random times, no communication")
