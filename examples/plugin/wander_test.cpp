// wander_test.cpp: eight drones wander for 30 s in a 300 m room; they spread out and stay inside.
#include <salsa/fixture.hpp>

#include <cstdio>

int main() {
  salsa::testing::Simulation sim(R"({"behavior": "wander", "drones": 8, "seed": 1,
                                     "map": {"name": "empty", "params": {"size": 300}}})",
                                 {SALSA_PLUGIN_FILE});
  sim.run(30);
  double spread = 0;
  for (salsa::Vec2 p : sim.positions()) {
    if (!sim.world().bounds().contains(p)) return std::fprintf(stderr, "a drone left the room\n"), 1;
    spread += salsa::distance(p, sim.world().bounds().centre()) / 8;
  }
  if (spread < 20) return std::fprintf(stderr, "drones stayed at the centre (mean distance %.1f m)\n", spread), 1;
  std::printf("mean distance from the centre after 30 s: %.1f m\n", spread);
}
