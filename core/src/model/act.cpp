// Act and physics: steering becomes velocity (through the air, with wind), the physics steps, the result is read back.
#include "salsa/core/model/simulation.hpp"

#include <cmath>
#include <string>

#include "model/physics.hpp"
#include "model/plugin_call.hpp"
#include "format.hpp"

namespace salsa {

using namespace detail;

namespace {

/// A drone's steering, or a failure naming its group's behavior when it is not a finite vector.
Vec2 finite_steering(Vec2 a, std::uint32_t group, std::size_t drone) {
  if (!a.finite())
    throw PluginFailure(behavior_kind, group, "decide returned a non-finite steering " + format::point(a) + " for drone " + std::to_string(drone));
  return a;
}

}  // namespace

// Act: add the steering to the velocity as it is, clamp the speed to max speed, hand the velocity to
// Box2D. Max force bounds each steering term (the SDK's helpers clamp to it), not a behavior's weighted
// sum of terms: table1's flocking applies 1.6 + 3 + 1 + 4 = 9.6 × max force at most.
void Simulation::act() {
  if (wind_active_) return act_in_wind();
  for (std::size_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.status[i] != DroneStatus::flying) continue;
    const std::uint32_t g = drones_.groups[i];
    const Vec2 a = finite_steering(drones_.steering[i], g, i);
    const Vec2 v = (drones_.velocities[i] + a).clamped(groups_[g].properties.max_speed);
    drones_.commanded[i] = v;
  }
  physics_->set_velocities(drones_.commanded, drones_.status);
}

Vec2 Simulation::wind_at(Vec2 p, double t) const {
  Vec2 w = setup_.wind.velocity + gusts_.value();
  if (const WindField* field = setup_.wind_field.get()) w += plugin_call(wind_kind, 0, [&] { return field->velocity(p, t); });
  return w;
}

// The wind where each flying drone is, at the step's start: asked once per drone and step (before the
// drones decide, so that they perceive the wind they will fly in). A field that would carry a drone
// through a wall in one step (or returns no number) stops the run, naming the plugin.
void Simulation::sample_wind() {
  const double t = time(), dt = setup_.dt;
  const bool field = setup_.wind_field != nullptr;
  for (std::size_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.status[i] != DroneStatus::flying) continue;
    const Vec2 p = drones_.positions[i];
    const Vec2 w = wind_at(p, t);
    if (field) {
      const DroneConfig& d = setup_.groups[drones_.groups[i]].drone;
      const double limit = wind_limit(d, dt), speed = w.length();
      if (!w.finite())
        throw PluginFailure(wind_kind, 0, "velocity at " + format::point(p) + ", t = " + format::figure(t) + " s gave a wind of " + format::point(w) +
                                              " m/s (allowed: finite numbers)");
      if (speed > limit * (1 + 1e-9))
        throw PluginFailure(wind_kind, 0, "velocity at " + format::point(p) + ", t = " + format::figure(t) + " s gave a wind of " + format::beyond(speed, limit) +
                                              " m/s with the test's constant wind and gusts; a drone at max_speed " + format::figure(d.max_speed) +
                                              " m/s carried by it moves more than min(radius " + format::number(d.radius) + " m, " +
                                              format::figure(box2d_max_step) + " m) per step (dt " + format::figure(dt) +
                                              " s) and could pass through a wall (allowed: at most " +
                                              (limit > 0 ? format::limit((limit)) : "0") + " m/s here)");
    }
    drones_.air.wind[i] = w;
  }
}

// Act in wind: the steering changes the air velocity, clamped to max speed; Box2D gets the ground
// velocity, air + the wind sampled at the drone's position when the step started.
void Simulation::act_in_wind() {
  for (std::size_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.status[i] != DroneStatus::flying) continue;
    const std::uint32_t g = drones_.groups[i];
    const Vec2 a = finite_steering(drones_.steering[i], g, i);
    const Vec2 air = (drones_.air.velocity[i] + a).clamped(groups_[g].properties.max_speed);
    drones_.air.velocity[i] = air;
    drones_.commanded[i] = air + drones_.air.wind[i];
  }
  physics_->set_velocities(drones_.commanded, drones_.status);
}

void Simulation::physics() {
  physics_->advance(geometry_, setup_.dt, setup_.velocity_iterations, setup_.position_iterations);
}

void Simulation::read_back() {
  physics_->read_back(drones_.positions, drones_.velocities);
  if (!wind_active_) return;
  // What the physics left of the ground velocity (a collision changes it) less the wind flown in.
  for (std::size_t i = 0; i < drones_.positions.size(); ++i)
    if (drones_.status[i] == DroneStatus::flying) drones_.air.velocity[i] = drones_.velocities[i] - drones_.air.wind[i];
  gusts_.advance(setup_.wind.gust_strength, setup_.wind.gust_time_scale, setup_.dt);
}

void Simulation::track_air() {
  for (std::size_t i = drones_.air.velocity.size(); i < drones_.velocities.size(); ++i) {
    drones_.air.velocity.push_back(drones_.velocities[i]);
    drones_.air.wind.push_back({});
  }
}

void Simulation::Drones::Air::columns(std::vector<StateColumn>& out) const {
  out.push_back(StateColumn::of("air_velocity", "m/s", "wind", "its velocity relative to the air", velocity));
  out.push_back(StateColumn::of("wind", "m/s", "wind", "the wind it flew in during the last step", wind));
}

}  // namespace salsa
