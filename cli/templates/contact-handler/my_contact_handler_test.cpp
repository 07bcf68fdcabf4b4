// my_contact_handler in a real simulation: the same flight (salsa's random_walk, same seed) finds targets at first
// sight with salsa's detect_targets, and fewer, but some, when my_contact_handler asks for 2 drones' sightings.
#include <string>

#include "test_preamble.hpp"

int main() {
  const std::string flight = R"("behavior": "random_walk", "drones": 10, "seed": 1,
                                "map": {"name": "empty", "params": {"size": 400}},
                                "targets": {"kind": "tree", "count": 200})";
  salsa::testing::Simulation first_sight("{" + flight + R"(, "contact_handlers": ["detect_targets"]})", {SALSA_PLUGIN_FILE});
  salsa::testing::Simulation confirmed("{" + flight + R"(, "contact_handlers": ["my_contact_handler"]})", {SALSA_PLUGIN_FILE});
  first_sight.run(30);
  confirmed.run(30);
  std::printf("found in 30 s: %zu at first sight, %zu confirmed\n", first_sight.targets_found(), confirmed.targets_found());
  CHECK(confirmed.targets_found() > 0);
  CHECK(confirmed.targets_found() < first_sight.targets_found());
  std::puts("my_contact_handler_test: ok");
  return 0;
}
