#pragma once
// A drone configuration: the physical and sensing properties shared by every drone of a test.
#include <string>
#include <vector>

namespace salsa {

struct DroneConfig {
  std::string name = "small";
  double camera_range = 15;       ///< m: targets within camera range (+ target radius) are seen
  double obstacle_range = 50.2;   ///< m: length of the obstacle rays
  double detection_range = 134;   ///< m: other drones within this range are neighbours
  double max_speed = 10;          ///< m/s
  double max_force = 0.3;         ///< largest velocity change of one steering term per step, m/s (the paper's convention)
  double radius = 1;              ///< m
  double mass = 1.5;              ///< kg
  int obstacle_rays = 8;          ///< rays evenly spread over 360°
  bool operator==(const DroneConfig&) const = default;
};

/// The named configurations every test may use ("small" is the paper's; see docs/test-format.md).
const std::vector<DroneConfig>& builtin_drone_configs();

}  // namespace salsa
