// my_map in a real simulation: the bounds its size gives, pillars on the grid and none at the centre,
// drones kept inside for 30 s; parameters it refuses fail the run with its message.
#include <cstring>
#include <stdexcept>

#include "test_preamble.hpp"

int main() {
  salsa::testing::Simulation sim(R"({"behavior": "random_walk", "drones": 8, "seed": 1,
                                     "map": {"name": "my_map", "params": {"size": 500}}})",
                                 {SALSA_PLUGIN_FILE});
  const salsa::Rect bounds = sim.world().bounds();
  CHECK((bounds == salsa::Rect{{0, 0}, {500, 500}}));
  CHECK(!sim.world().is_free({50, 50}, 0));          // a pillar (spacing 50 m)
  CHECK(sim.world().is_free(bounds.centre(), 40));   // clear around the centre
  sim.run(30);
  for (salsa::Vec2 p : sim.positions()) CHECK(bounds.contains(p));
  bool refused = false;
  try {
    salsa::testing::Simulation wide(R"({"behavior": "random_walk", "map": {"name": "my_map", "params": {"pillar": 60}}})",
                                    {SALSA_PLUGIN_FILE});
  } catch (const std::runtime_error& e) {
    refused = std::strstr(e.what(), "pillar: must be smaller than spacing") != nullptr;
  }
  CHECK(refused);
  std::puts("my_map_test: ok");
  return 0;
}
