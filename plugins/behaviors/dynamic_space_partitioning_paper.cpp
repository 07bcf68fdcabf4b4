// Dynamic space partitioning as the SALSA paper defines it (each drone random-walks in a disc around
// its point): the class is published in the SDK (salsa/behaviors/dynamic_space_partitioning_paper.hpp);
// this file registers it.
#include <salsa/behaviors/dynamic_space_partitioning_paper.hpp>
#include <salsa/sdk.hpp>

SALSA_BEHAVIOR(salsa::behaviors::DynamicSpacePartitioningPaper, "dynamic_space_partitioning_paper",
               "The SALSA paper's partitioning: spreading virtual points, each drone random-walks in a disc around its own")
