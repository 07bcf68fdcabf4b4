#pragma once
// test_limits' proof that no drone passes a wall, shared by test_light (the same layouts in light mode).
#include <memory>

#include "salsa/core/model/simulation.hpp"

namespace salsa_test {

/// A drone of `radius` m whose velocity can reach `speed` m/s in one step.
inline salsa::DroneConfig racer(double radius, double speed) {
  salsa::DroneConfig d;
  d.radius = radius;
  d.max_speed = speed;
  d.max_force = 1000;
  d.obstacle_rays = 0;
  return d;
}

/// The x of the wall in every wall layout.
inline constexpr double x_wall = 100;

/// A map 200 m wide and `height` m tall with a wall at x = 100 from bottom to top (`wall` 0: a map line,
/// 1: a solid polygon 20 m thick, 2: a polygon 1 mm thin) and one racer of `radius` m at `speed`, flown
/// by `behavior` at `dt` and `lag`. The caller places the spawn point.
inline salsa::SimulationSetup wall_layout(int wall, double height, double radius, double speed, double dt, int lag,
                                          std::shared_ptr<salsa::Behavior> behavior) {
  salsa::SimulationSetup setup;
  setup.map.bounds = {{0, 0}, {200, height}};
  if (wall == 0) setup.map.lines = {{{x_wall, 0}, {x_wall, height}}};
  const double thickness = wall == 1 ? 20 : 0.001;
  if (wall > 0) setup.map.obstacles = {{{x_wall, 0}, {x_wall + thickness, 0}, {x_wall + thickness, height}, {x_wall, height}}};
  setup.groups[0].drone = racer(radius, speed);
  setup.dt = dt;
  setup.decision_lag = lag;
  setup.groups[0].drones = 1;
  setup.groups[0].spawn_radius = 1e-9;
  setup.groups[0].behavior = std::move(behavior);
  return setup;
}

}  // namespace salsa_test
