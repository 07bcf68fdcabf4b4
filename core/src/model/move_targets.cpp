// Move: one step of the targets of a kind that moves them (people walking), after the drones' step.
#include "salsa/core/model/simulation.hpp"

#include <cmath>
#include <string>

#include "model/plugin_call.hpp"
#include "model/world_views.hpp"
#include "format.hpp"

namespace salsa {

using namespace detail;

// The kind moves every target from where it is (the positions the drones sensed this step) with the
// targets' own random stream and a world without drones, so the paths are the same for every behavior
// of a repeat. The core holds it to its contract: a target stays where it was or ends on a free point
// at most max_speed × dt away, so it never enters an obstacle or leaves the map and the lists of
// targets in reach (sense.cpp) stay correct. The grid is rebuilt on the new positions: O(targets).
void Simulation::move_targets() {
  Targets& t = targets_;
  const TargetKind& kind = *setup_.target_kind;
  const StateView world(setup_.map, geometry_, groups_[0].properties, time(), setup_.dt);
  t.before = t.positions;
  plugin_call(target_kind, 0, [&] { kind.move(t.positions, t.velocities, world, t.rng); });
  const double most = t.max_speed * setup_.dt;
  for (std::size_t i = 0; i < t.positions.size(); ++i) {
    const Vec2 from = t.before[i], to = t.positions[i];
    if (to == from) continue;
    const char* why = !to.finite()                                           ? "is not a point"
                      : distance_squared(from, to) > most * most * (1 + 1e-9) ? "is farther than max_speed × dt"
                      : !geometry_.is_free(to, t.radius)                      ? "is inside an obstacle or outside the bounds"
                                                                              : nullptr;
    if (why)
      throw PluginFailure(target_kind, 0, "move() took target " + std::to_string(i) + " from " + format::point(from) + " to " +
                                              format::point(to) + ", which " + why + " (allowed: a free point at most " +
                                              format::figure(most) + " m away, or where it was)");
  }
  for (std::size_t i = 0; i < t.positions.size(); ++i) t.states[i].position = t.positions[i];
  t.travel += most;
  t.grid.build(t.positions, t.cell);
}

}  // namespace salsa
