// dwell_test.cpp: the same flight finds fewer nests when a drone must watch each for 3 s.
#include <salsa/fixture.hpp>

#include <cstdio>

std::size_t found(double dwell) {
  salsa::testing::Simulation sim(R"({"behavior": "random_walk", "drones": 10, "seed": 2,
      "map": {"name": "empty", "params": {"size": 300}}, "targets": {"kind": "nest", "count": 100},
      "contact_handlers": [{"name": "dwell_detect", "params": {"dwell": )" + std::to_string(dwell) + "}}]}",
                                 {SALSA_PLUGIN_FILE});
  sim.run(60);
  return sim.targets_found();
}

int main() {
  const std::size_t at_sight = found(0), after_3s = found(3);
  std::printf("nests found in 60 s: %zu at first sight, %zu with a 3 s dwell\n", at_sight, after_3s);
  return at_sight > 10 && after_3s < at_sight ? 0 : 1;
}
