#include "salsa/core/model/drone_config.hpp"

#include <cmath>

namespace salsa {

const Schema<DroneConfig, DroneSection>& drone_schema() {
  // The ranges are what a test file may hold (the physics adds check_drone's step limit on top); the
  // step is the finest a slider moves.
  static const Schema<DroneConfig, DroneSection> schema{
      field<&DroneConfig::camera_range>({"camera_range", 15, 0, 1e4, "m", "targets within this range (+ the target's radius) are seen", 0.5}, DroneSection::body),
      field<&DroneConfig::obstacle_range>({"obstacle_range", 50.2, 0, 1e4, "m", "length of the obstacle rays", 0.5}, DroneSection::body),
      field<&DroneConfig::detection_range>({"detection_range", 134, 0, 1e5, "m", "other drones within this range are neighbours", 0.5}, DroneSection::body),
      field<&DroneConfig::max_speed>({"max_speed", 10, 1e-3, 1e3, "m/s", "speed limit, applied after steering", 1e-3}, DroneSection::body),
      field<&DroneConfig::max_force>({"max_force", 0.3, 1e-6, 1e3, "m/s per step", "largest velocity change of one steering term per step", 1e-6}, DroneSection::body),
      field<&DroneConfig::radius>({"radius", 1, 1e-2, 100, "m", "the drone's body, a circle", 0.01}, DroneSection::body),
      field<&DroneConfig::mass>({"mass", 1.5, 1e-3, 1e6, "kg", "mass of the body (collisions)", 1e-3}, DroneSection::body),
      field<&DroneConfig::obstacle_rays>({"obstacle_rays", 8, 0, 64, "", "obstacle rays, evenly spread over 360°", 1}, DroneSection::body),
      field<&DroneConfig::battery_capacity>({"battery_capacity", 0, 0, 1e6, "Wh", "battery energy; 0: no battery model (never runs flat)", 0.1}, DroneSection::energy, false),
      field<&DroneConfig::blade_power>({"blade_power", 79.86, 0, 1e6, "W", "P0: blade profile power in hover (Zeng et al. 2019)", 0.01}, DroneSection::energy, false),
      field<&DroneConfig::induced_power>({"induced_power", 88.63, 0, 1e6, "W", "Pi: induced power in hover", 0.01}, DroneSection::energy, false),
      field<&DroneConfig::tip_speed>({"tip_speed", 120, 1, 1e3, "m/s", "U: rotor blade tip speed", 0.1}, DroneSection::energy, false),
      field<&DroneConfig::induced_velocity>({"induced_velocity", 4.03, 0.01, 100, "m/s", "v0: mean rotor induced velocity in hover", 0.01}, DroneSection::energy, false),
      field<&DroneConfig::parasite_drag>({"parasite_drag", 0.0092, 0, 100, "kg/m", "k = d0 rho s A / 2: fuselage drag term, k V^3 W", 1e-4}, DroneSection::energy, false),
      field<&DroneConfig::charge_power>({"charge_power", 0, 0, 1e6, "W", "charging power at the group's base; 0: bases do not recharge", 0.1}, DroneSection::energy, false),
      field<&DroneConfig::charge_radius>({"charge_radius", 5, 0, 1e4, "m", "a drone slower than 1 m/s this close to its base charges", 0.1}, DroneSection::energy, false),
      field<&DroneConfig::return_to_base>({"return_to_base", 0, 0, 1, "", "1: the core flies the drone home to charge when its energy left is what the way home needs plus the reserve, then back to where it left off", 1}, DroneSection::returning, false),
      field<&DroneConfig::return_reserve>({"return_reserve", 0, 0, 1e6, "Wh", "energy a returning drone keeps on arrival at the base", 0.01}, DroneSection::returning, false),
      field<&DroneConfig::resume_charge>({"resume_charge", 1, 0, 1, "", "battery fraction at which a charging drone flies out again", 0.01}, DroneSection::returning, false),
      // Sensor noise: not part of the world key, so tests that differ only in noise fly in the same world.
      field<&DroneConfig::position_noise>({"position_noise", 0, 0, 1e3, "m", "sd of the noise on each axis of the drone's own perceived position", 0.01}, DroneSection::noise, false),
      field<&DroneConfig::neighbour_noise>({"neighbour_noise", 0, 0, 1e3, "m", "sd of the noise on each axis of a neighbour's perceived offset", 0.01}, DroneSection::noise, false),
      field<&DroneConfig::obstacle_noise>({"obstacle_noise", 0, 0, 1e3, "m", "sd of the noise on each obstacle ray's hit distance", 0.01}, DroneSection::noise, false),
      field<&DroneConfig::miss_probability>({"miss_probability", 0, 0, 1, "", "chance that a target in view goes undetected in a step", 0.001}, DroneSection::noise, false),
      field<&DroneConfig::false_detection_rate>({"false_detection_rate", 0, 0, 100, "1/s", "false detections (phantom targets) per drone and second", 0.01}, DroneSection::noise, false),
  };
  return schema;
}

bool section_in_use(const DroneConfig& d, DroneSection section) {
  switch (section) {
    case DroneSection::body: return true;
    case DroneSection::energy: return d.battery_capacity > 0;
    case DroneSection::returning: return d.battery_capacity > 0 && d.return_to_base > 0;
    case DroneSection::noise:
      return d.position_noise > 0 || d.neighbour_noise > 0 || d.obstacle_noise > 0 || d.miss_probability > 0 ||
             d.false_detection_rate > 0;
  }
  return true;
}

double flight_power(const DroneConfig& d, double v) {
  const double v2 = v * v, v02 = d.induced_velocity * d.induced_velocity;
  const double blade = d.blade_power * (1 + 3 * v2 / (d.tip_speed * d.tip_speed));
  const double induced = d.induced_power * std::sqrt(std::sqrt(1 + v2 * v2 / (4 * v02 * v02)) - v2 / (2 * v02));
  return blade + induced + d.parasite_drag * v2 * v;
}

const std::vector<DroneConfig>& builtin_drone_configs() {
  // name, camera, obstacle, detection range (m), max speed (m/s), max force (m/s per step), radius (m),
  // mass (kg), rays. "small" is Table I of the SALSA paper; the others scale it for larger airframes.
  static const std::vector<DroneConfig> configs{
      {"small", 15, 50.2, 134, 10, 0.3, 1.0, 1.5, 8},
      {"medium", 25, 60, 200, 15, 0.4, 1.5, 4.0, 8},
      {"large", 40, 80, 300, 20, 0.5, 2.5, 12.0, 12},
  };
  return configs;
}

}  // namespace salsa
