#pragma once
// A drone configuration: the physical and sensing properties shared by every drone of a test, and
// their schema, declared once: the test reader and writer, timed changes (drone.<name>), sweeps, the
// desktop's panel and `salsa describe drone` are all driven by drone_schema(). Adding a property is a
// member here, one line in drone_schema() (drone_config.cpp) and its use.
#include <string>
#include <string_view>
#include <vector>

#include "salsa/parameters.hpp"

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

/// One property of DroneConfig: its declaration (name, default = the "small" drone, range, unit,
/// meaning; step 1 for a whole number) and where it lives.
struct DroneProperty {
  Parameter spec;
  double DroneConfig::*real = nullptr;  ///< a number, or
  int DroneConfig::*whole = nullptr;    ///< a whole number
  double get(const DroneConfig& d) const { return real ? d.*real : static_cast<double>(d.*whole); }
  void set(DroneConfig& d, double v) const {
    if (real) d.*real = v;
    else d.*whole = static_cast<int>(v);
  }
};

/// Every drone property, in file order.
const std::vector<DroneProperty>& drone_schema();
/// The property called `name`, or nullptr.
const DroneProperty* find_drone_property(std::string_view name);
/// "camera_range, obstacle_range, ...": the names, for messages.
std::string drone_property_names();

/// The named configurations every test may use ("small" is the paper's; see docs/test-format.md).
const std::vector<DroneConfig>& builtin_drone_configs();

}  // namespace salsa
