#include "salsa/core/drone_config.hpp"

namespace salsa {

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
