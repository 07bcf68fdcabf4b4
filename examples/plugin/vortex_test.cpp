// vortex_test.cpp: drones that keep still in the air (zero air velocity) are carried round the vortex.
// Outside the core the wind is speed × core / r, so a drone at r = 100 m (core 50 m, 5 m/s) goes round
// at 2.5 m/s: an angle of 2.5 t / 100 rad after t s, at the same distance from the centre.
#include <salsa/fixture.hpp>

#include <cmath>
#include <cstdio>
#include <memory>

namespace {
class Drift final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override { return -me.air_velocity; }
};
int fail(const char* what) { return std::fprintf(stderr, "vortex_test: %s\n", what), 1; }
}  // namespace

int main() {
  const salsa::Vec2 centre{500, 500};
  salsa::testing::Simulation sim(std::make_shared<Drift>(),
                                 R"({"drones": 1, "seed": 2, "map": {"name": "empty", "params": {"size": 1000}},
                                     "spawn": {"point": [600, 500], "radius": 0.001},
                                     "wind": {"field": {"name": "vortex", "params": {"centre_x": 500, "centre_y": 500, "core": 50, "speed": 5}}}})",
                                 {SALSA_PLUGIN_FILE});
  const salsa::Vec2 start = sim.positions()[0] - centre;
  sim.run(40);
  const salsa::Vec2 end = sim.positions()[0] - centre;
  const double turned = std::atan2(start.cross(end), start.dot(end));  // counter-clockwise > 0
  const double expected = 2.5 * 40 / start.length();
  std::printf("from r = %.3f m to r = %.3f m, turned %.4f rad (expected %.4f)\n", start.length(), end.length(), turned, expected);
  if (std::abs(turned - expected) > 0.01 * expected) return fail("the drone did not go round at core / r × speed");
  if (std::abs(end.length() - start.length()) > 0.5) return fail("the drone left its circle");
  std::puts("vortex_test: ok");
  return 0;
}
