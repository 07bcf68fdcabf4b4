#pragma once
// A drone configuration: the physical and sensing properties shared by every drone of a test, and
// their schema, declared once: the test reader and writer, timed changes (drone.<name>), sweeps, the
// desktop's panel and `salsa describe drone` are all driven by drone_schema() (schema.hpp). Adding a
// property is a member here, one line in drone_schema() (drone_config.cpp) and its use.
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/model/schema.hpp"
#include "salsa/parameters.hpp"
#include "salsa/vec2.hpp"

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
  // Energy (off while battery_capacity is 0): a battery, the rotary-wing power model of Zeng, Xu &
  // Zhang (2019), P(V) = P0 (1 + 3V²/U²) + Pi (sqrt(1 + V⁴/(4 v0⁴)) − V²/(2 v0²))^½ + k V³, with
  // their example airframe's values, and charging at the group's base.
  double battery_capacity = 0;    ///< Wh; 0: no battery model, the drone never runs flat
  double blade_power = 79.86;     ///< W: P0, blade profile power in hover
  double induced_power = 88.63;   ///< W: Pi, induced power in hover
  double tip_speed = 120;         ///< m/s: U, rotor blade tip speed
  double induced_velocity = 4.03; ///< m/s: v0, mean rotor induced velocity in hover
  double parasite_drag = 0.0092;  ///< kg/m: k = ½ d0 ρ s A (fuselage drag ratio, air density, rotor solidity, disc area)
  double charge_power = 0;        ///< W a drone charges with at its base; 0: bases do not recharge
  double charge_radius = 5;       ///< m from the base within which a drone slower than 1 m/s charges
  // Return to base (off while return_to_base is 0; return_to_base.cpp): the core takes a drone from its
  // behavior when its energy left is what the way home needs plus the reserve, charges it at the base
  // and flies it back to where it left off.
  int return_to_base = 0;         ///< 1: the core brings the drone home to charge, whatever its behavior
  double return_reserve = 0;      ///< Wh kept on arrival at the base
  double resume_charge = 1;       ///< battery fraction at which a charging drone flies out again
  // Sensor noise (off while all are 0; simulation.cpp, sense and perceive): what a drone perceives
  // departs from the truth; the world, the contact handlers and the outputs keep the truth.
  double position_noise = 0;      ///< m: sd of Gaussian noise on each axis of the drone's own perceived position
  double neighbour_noise = 0;     ///< m: sd of Gaussian noise on each axis of a neighbour's offset from the drone
  double obstacle_noise = 0;      ///< m: sd of Gaussian noise on each obstacle ray's hit distance
  double miss_probability = 0;    ///< chance that a target in view goes undetected in a step
  double false_detection_rate = 0;  ///< 1/s: false detections (phantom targets) per drone, a Poisson process
  bool operator==(const DroneConfig&) const = default;
};

/// Where a property belongs: the body and sensors every drone has, the energy model (in use while
/// battery_capacity > 0), return to base (in use while return_to_base is 1; the desktop shows it with
/// the energy model) or sensor noise (in use while any of its properties is not 0). A section not in
/// use is left out of config.json, so a test without it is written as before it existed; the desktop
/// folds each optional section away.
enum class DroneSection { body, energy, noise, returning };

/// One property of DroneConfig: its declaration (default = the "small" drone; step 1 for a whole
/// number), where it lives, its section and whether it shapes the world (schema.hpp).
using DroneProperty = Field<DroneConfig, DroneSection>;

/// Whether `section` is in use for `d` (always, for the body).
bool section_in_use(const DroneConfig& d, DroneSection section);

/// Power drawn in flight at speed `v` (m/s), W: the model above.
double flight_power(const DroneConfig& d, double v);

/// The energy (J) a drone of configuration `d` needs to fly `distance` m home and stop there, its way
/// setting off along the unit vector `direction`: turning its ground velocity `velocity` onto the way,
/// cruising at full air speed (at the ground speed along `direction` in the `wind` at the drone),
/// braking to rest, with the power model above; `dt` is the time step its max force is per. +inf when
/// the wind allows no headway home. See docs/test-format.md, "Return to base".
double energy_home(const DroneConfig& d, double distance, Vec2 direction, Vec2 velocity, Vec2 wind, double dt);

/// Every drone property, in file order.
const Schema<DroneConfig, DroneSection>& drone_schema();

/// The named configurations every test may use ("small" is the paper's; see docs/test-format.md).
const std::vector<DroneConfig>& builtin_drone_configs();

}  // namespace salsa
