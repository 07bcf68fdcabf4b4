// my_target targets in a real simulation: drones of salsa's built-in random_walk find some in 60 s, and
// more when they see as far as their cameras reach (visibility 1), on the same flight (same seed).
#include "test_preamble.hpp"

int main() {
  salsa::testing::Simulation sim(R"({"behavior": "random_walk", "drones": 10, "seed": 1,
                                     "map": {"name": "empty", "params": {"size": 400}},
                                     "targets": {"kind": "my_target", "count": 100}})",
                                 {SALSA_PLUGIN_FILE});
  salsa::testing::Simulation far(R"({"behavior": "random_walk", "drones": 10, "seed": 1,
                                     "map": {"name": "empty", "params": {"size": 400}},
                                     "targets": {"kind": "my_target", "count": 100, "params": {"visibility": 1}}})",
                                 {SALSA_PLUGIN_FILE});
  CHECK(sim.targets() == 100);
  sim.run(60);
  far.run(60);
  std::printf("found in 60 s: %zu of 100, %zu with visibility 1\n", sim.targets_found(), far.targets_found());
  CHECK(sim.targets_found() > 0);
  CHECK(far.targets_found() > sim.targets_found());
  std::puts("my_target_test: ok");
  return 0;
}
