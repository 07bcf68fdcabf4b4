// Dynamic space partitioning, salsa's version (each drone sweeps its region): the class is published
// in the SDK (salsa/behaviors/dynamic_space_partitioning.hpp) so that a plugin can derive from it;
// this file registers it.
#include <salsa/behaviors/dynamic_space_partitioning.hpp>
#include <salsa/sdk.hpp>

SALSA_BEHAVIOR(salsa::behaviors::DynamicSpacePartitioning, "dynamic_space_partitioning",
               "Shares the free area out among the drones by spreading virtual points; each sweeps its region")
