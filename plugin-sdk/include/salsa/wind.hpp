#pragma once
// Wind fields: the air's velocity over the map as a plugin of kind `wind` (a sea breeze, a vortex, a
// street canyon). A test's "wind" adds a field's velocity to its constant wind and its gusts; a drone's
// max speed is relative to the air, so the wind carries it (docs/test-format.md#wind).
#include "salsa/parameters.hpp"
#include "salsa/vec2.hpp"

namespace salsa {

class WindField : public Configurable {
 public:
  /// The field's air velocity (m/s) at point `p` (m) at time `t` (s since start). Asked once per flying
  /// drone per step, at the drone's position when the step starts, on the stepping thread; keep it
  /// cheap and deterministic (the same p and t give the same velocity). It must be finite, and the
  /// test's whole wind (constant + gusts + field) at most the speed a drone can be carried without
  /// crossing a wall in one step, (min(radius, 2 m) / dt) − max_speed: else the run stops, naming this
  /// plugin.
  virtual Vec2 velocity(Vec2 p, double t) const = 0;
};

}  // namespace salsa
