// my_metric in a real simulation: after 30 s, drones of salsa's built-in flocking, weighted towards
// matching their neighbours' velocity, fly the same way (polarisation near 1); random_walk drones do not.
#include "test_preamble.hpp"

int main() {
  salsa::testing::Simulation flock(R"({"behavior": {"name": "flocking", "params": {"alignment_weight": 5}},
                                       "drones": 12, "seed": 1, "metrics": ["my_metric"]})",
                                   {SALSA_PLUGIN_FILE});
  salsa::testing::Simulation walk(R"({"behavior": "random_walk", "drones": 12, "seed": 1, "metrics": ["my_metric"]})",
                                  {SALSA_PLUGIN_FILE});
  flock.run(30);
  walk.run(30);
  const double aligned = flock.metric("polarisation"), random = walk.metric("polarisation");
  std::printf("polarisation after 30 s: flocking %.3f, random_walk %.3f\n", aligned, random);
  CHECK(aligned > 0.9 && aligned <= 1 + 1e-9);
  CHECK(random >= 0 && random < 0.6);
  std::puts("my_metric_test: ok");
  return 0;
}
