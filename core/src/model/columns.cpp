// The drones' state as named columns: each model's per-drone arrays, declared once here with their
// name, unit and meaning, read by name without a copy (columns.hpp).
#include "salsa/core/model/simulation.hpp"

#include <type_traits>

namespace salsa {
namespace {

template <class T>
constexpr StateColumn::Type type_of() {
  if constexpr (std::is_same_v<T, std::uint32_t>) return StateColumn::Type::u32;
  else if constexpr (sizeof(T) == 1) return StateColumn::Type::u8;  // flags, DroneStatus
  else return StateColumn::Type::f64;                               // double, and Vec2 as two
}

/// A column over `values` (a vector of double, Vec2, uint32, uint8 or DroneStatus).
template <class T>
StateColumn view(std::string_view name, std::string_view unit, std::string_view model, std::string_view meaning,
            const std::vector<T>& values) {
  constexpr bool vector = std::is_same_v<T, Vec2>;
  static_assert(!vector || sizeof(Vec2) == 2 * sizeof(double), "a Vec2 is two doubles, x then y");
  return {name, unit, meaning, model, vector ? StateColumn::Type::f64 : type_of<T>(), vector ? 2u : 1u, values.data(), values.size()};
}

}  // namespace

std::vector<StateColumn> Simulation::columns() const {
  const Drones& d = drones_;
  std::vector<StateColumn> out{
      view("position", "m", "drone", "where the drone is", d.positions),
      view("velocity", "m/s", "drone", "its ground velocity", d.velocities),
      view("steering", "m/s", "drone", "the velocity change its behavior asked for in the last decide", d.steering),
      view("commanded", "m/s", "drone", "the velocity the last act phase handed to the physics", d.commanded),
      view("group", "", "drone", "its group's index in the test's groups", d.groups),
      view("status", "", "drone", "0 flying, 1 landed, 2 failed, 3 removed", d.status),
      view("status_since", "s", "drone", "when its status began (0 while it has flown from the start)", d.since),
      view("camera_works", "", "fleet", "1 while its camera works, 0 once the camera failed", d.camera),
      view("energy_used", "J", "fleet", "energy drawn from its battery so far", d.used),
      view("battery_left", "J", "fleet", "energy left in its battery (inf without a battery model)", d.charge),
      view("failure_exposure", "", "fleet", "its failure clock: integral of dt / drone_mtbf so far", d.exposure),
      view("failure_due", "", "fleet", "the Exp(1) draw its failure clock fails the drone at", d.due),
      view("camera_failure_exposure", "", "fleet", "its camera's failure clock: integral of dt / camera_mtbf", d.camera_exposure),
      view("camera_failure_due", "", "fleet", "the Exp(1) draw its camera's clock fails the camera at", d.camera_due),
      view("obstacle_hits", "", "sensing", "how many of its obstacle rays hit something in the last sense", d.hit_counts),
  };
  if (wind_active_) {
    out.push_back(view("air_velocity", "m/s", "wind", "its velocity relative to the air", d.air));
    out.push_back(view("wind", "m/s", "wind", "the wind it flew in during the last step", d.wind));
  }
  return out;
}

StateColumn Simulation::column(std::string_view name) const {
  for (const StateColumn& c : columns())
    if (c.name == name) return c;
  return {};
}

}  // namespace salsa
