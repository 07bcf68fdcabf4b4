// my_behavior in a real simulation: 8 drones for 30 s in a 300 m room. They stay inside and keep flying
// (drones that only drift on their start velocity fly about 120 m). Parameters as in a test file:
// "behavior": {"name": "my_behavior", "params": {"turn_rate": 2}}.
#include "test_preamble.hpp"

int main() {
  salsa::testing::Simulation sim(R"({"behavior": "my_behavior", "drones": 8, "seed": 1,
                                     "map": {"name": "empty", "params": {"size": 300}}})",
                                 {SALSA_PLUGIN_FILE});
  sim.run(30);
  for (salsa::Vec2 p : sim.positions()) CHECK(sim.world().bounds().contains(p));
  const double flown = sim.metric("mean_distance");  // m per drone: salsa's distance_flown metric
  std::printf("mean distance flown in 30 s: %.0f m\n", flown);
  CHECK(flown > 150);  // at most 10 m/s: 300 m
  std::puts("my_behavior_test: ok");
  return 0;
}
