#pragma once
// Internal to libsalsa: what the Simulation asks of its physics, Box2D's (physics_world.hpp) or salsa's
// own light physics (light_world.hpp). Per-step calls take whole arrays indexed by drone id, so the
// per-drone work stays inside one loop of the implementation; only set-up and rare status changes are
// per drone.
#include <cstddef>
#include <cstdint>
#include <span>

#include "salsa/contact.hpp"
#include "salsa/core/model/drone_config.hpp"
#include "salsa/core/model/static_geometry.hpp"
#include "salsa/world.hpp"

namespace salsa {

class Physics {
 public:
  virtual ~Physics() = default;
  /// Drone `id` (the next one: ids are appended in order), disabled from the start unless `enabled`.
  virtual void add_drone(std::uint32_t id, Vec2 position, Vec2 velocity, const DroneConfig& config, bool enabled) = 0;
  /// Forgets drones [n, count): set-up and live changes rebuild from there.
  virtual void remove_drones_from(std::size_t n) = 0;
  /// Stops drone `id` for good: velocity zero, no longer collides or is collided with. Nothing if it is
  /// disabled already.
  virtual void disable(std::uint32_t id) = 0;
  /// Each flying drone's velocity for the next step (m/s); the others' are left as they are.
  virtual void set_velocities(std::span<const Vec2> velocities, std::span<const DroneStatus> status) = 0;
  /// One step of `dt` s. `geometry` is the simulation's segment grid (Box2D has its own copy of the
  /// walls); the iterations are Box2D's solver settings.
  virtual void advance(const StaticGeometry& geometry, double dt, int velocity_iterations, int position_iterations) = 0;
  /// Every drone's position and velocity after the last step, into arrays of the drone count.
  virtual void read_back(std::span<Vec2> positions, std::span<Vec2> velocities) const = 0;
  /// Drone–drone and drone–obstacle contacts that began during the last step, in a fixed order.
  virtual std::span<const ContactEvent> begun() const = 0;
};

}  // namespace salsa
