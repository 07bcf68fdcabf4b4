// my_wind in a real simulation: drones that keep still in the air (zero air velocity) are carried by
// the breeze alone. Over the sea they drift inland at `speed`; well inland, beyond its reach, they stay.
#include "test_preamble.hpp"

#include <cmath>
#include <memory>

namespace {
/// Holds its air velocity at zero: the drone goes where the wind takes it.
class Drift final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override { return -me.air_velocity; }
};

/// Drone 0's position after `seconds`, its group spawned at `y` on a 1000 m map (coast at y = 300).
salsa::Vec2 after(double seconds, double y, salsa::Vec2& start) {
  salsa::testing::Simulation sim(std::make_shared<Drift>(),
                                 R"({"drones": 1, "seed": 1, "map": {"name": "empty", "params": {"size": 1000}},
                                     "spawn": {"point": [500, )" + std::to_string(y) + R"(], "radius": 0.001},
                                     "wind": {"field": {"name": "my_wind", "params": {"speed": 4, "coast": 300}}}})",
                                 {SALSA_PLUGIN_FILE});
  start = sim.positions()[0];
  sim.run(seconds);
  return sim.positions()[0];
}
}  // namespace

int main() {
  salsa::Vec2 start;
  // Over the sea (y 800, 500 m beyond the coast) for 20 s: 80 m inland at 4 m/s.
  const salsa::Vec2 sea = after(20, 800, start);
  std::printf("over the sea: from (%.2f, %.2f) to (%.2f, %.2f)\n", start.x, start.y, sea.x, sea.y);
  // Still air from the first step: the breeze alone, to the rounding of Box2D's float positions.
  CHECK(std::abs((sea.y - start.y) - (-80.0)) < 0.1);
  CHECK(std::abs(sea.x - start.x) < 1.0);
  // Far inland (y 50, 250 m from the coast, beyond the 200 m reach): calm, the drone stays put.
  const salsa::Vec2 land = after(20, 50, start);
  std::printf("inland: from (%.2f, %.2f) to (%.2f, %.2f)\n", start.x, start.y, land.x, land.y);
  CHECK(salsa::distance(land, start) < 0.5);
  std::puts("my_wind_test: ok");
  return 0;
}
