// rings_test.cpp: the walls are where the parameters put them, and drones starting inside stay on the map.
#include <salsa/fixture.hpp>

int main() {
  salsa::testing::Simulation sim(R"({"behavior": "random_walk", "drones": 6, "seed": 4,
                                     "map": {"name": "rings", "params": {"rings": 4, "spacing": 50}}})",
                                 {SALSA_PLUGIN_FILE});
  const salsa::MapData& map = sim.world().map();
  if (map.lines.size() != 4 || map.bounds.width() != 500 || map.spawn != salsa::Vec2{250, 250}) return 1;
  sim.run(20);
  for (salsa::Vec2 p : sim.positions())
    if (!map.bounds.contains(p)) return 1;
  return 0;
}
