// The drones' state as named columns (columns.hpp): the drone's own here, then each model's, declared in
// its file (fleet.cpp, sense.cpp, act.cpp).
#include "salsa/core/model/simulation.hpp"

namespace salsa {
namespace {

/// `d`'s columns: the drone's own, then each model's (the wind's while `wind`, return to base's while
/// `errands`).
template <class Drones>
std::vector<StateColumn> columns_of(const Drones& d, bool wind, bool errands) {
  std::vector<StateColumn> out{
      StateColumn::of("position", "m", "drone", "where the drone is", d.positions),
      StateColumn::of("velocity", "m/s", "drone", "its ground velocity", d.velocities),
      StateColumn::of("steering", "m/s", "drone", "the velocity change its behavior asked for in the last decide", d.steering),
      StateColumn::of("commanded", "m/s", "drone", "the velocity the last act phase handed to the physics", d.commanded),
      StateColumn::of("group", "", "drone", "its group's index in the test's groups", d.groups),
      StateColumn::of("status", "", "drone", "0 flying, 1 landed, 2 failed, 3 removed", d.status),
      StateColumn::of("status_since", "s", "drone", "when its status began (0 while it has flown from the start)", d.since),
  };
  d.fleet.columns(out);
  d.sensing.columns(out);
  if (wind) d.air.columns(out);
  if (errands) d.errands.columns(out);
  for (const ModelState& m : d.models) m.columns(out);
  return out;
}

}  // namespace

// air: once the test has had wind; errands: once a group has returned to base
std::vector<StateColumn> Simulation::columns() const { return columns_of(drones_, wind_active_, !drones_.errands.state.empty()); }

std::vector<StateColumn> Simulation::declared_columns() {
  std::vector<StateColumn> out = columns_of(Drones{}, true, true);
  for (StateColumn& c : out) c.data = nullptr;
  return out;
}

StateColumn Simulation::column(std::string_view name) const {
  for (const StateColumn& c : columns())
    if (c.name == name) return c;
  return {};
}

}  // namespace salsa
