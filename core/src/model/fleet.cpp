// The fleet model in the step: batteries drain and charge, failure clocks run, drones are grounded.
#include "salsa/core/model/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "model/physics.hpp"
#include "model/streams.hpp"
#include "format.hpp"

namespace salsa {

using namespace detail;

// Fleet: each flying drone's battery drains by the power its speed over the step takes (or charges on
// its base), return to base decides its errand on the energy left (return_to_base.cpp), and its failure
// clocks advance. An empty battery lands the drone, a due failure grounds
// it, at the end of this step. Nothing to do (and no cost) without batteries or failure rates.
void Simulation::fleet() {
  const double dt = setup_.dt;
  const FailureSetup& f = setup_.failures;
  bool batteries = false, returning = false;
  for (const GroupSetup& g : setup_.groups) {
    batteries = batteries || g.drone.battery_capacity > 0;
    returning = returning || (g.drone.battery_capacity > 0 && g.drone.return_to_base > 0);
  }
  if (!batteries && f.drone_mtbf <= 0 && f.camera_mtbf <= 0) return;
  // Return to base's columns, once a group has it (and for drones added since).
  if (returning || !drones_.errands.state.empty()) drones_.errands.grow(drones_.positions.size());
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.status[i] != DroneStatus::flying) continue;
    const GroupSetup& g = setup_.groups[drones_.groups[i]];
    if (g.drone.battery_capacity > 0) {
      const double speed = drones_.velocities[i].length();
      const bool on_base = g.drone.charge_power > 0 && speed < 1 &&
                           distance(drones_.positions[i], groups_[drones_.groups[i]].base) <= g.drone.charge_radius;
      if (on_base) {
        drones_.fleet.charge[i] = std::min(drones_.fleet.charge[i] + g.drone.charge_power * dt, g.drone.battery_capacity * 3600);
      } else {
        // Power is drawn for the speed through the air (the ground speed without wind). The step that
        // empties the battery draws only what is left: a battery never gives more than it holds.
        const double energy = std::min(flight_power(g.drone, wind_active_ ? drones_.air.velocity[i].length() : speed) * dt, drones_.fleet.charge[i]);
        drones_.fleet.used[i] += energy;
        drones_.fleet.charge[i] -= energy;
        if (drones_.fleet.charge[i] <= 0) {
          drones_.fleet.charge[i] = 0;
          ground(i, DroneStatus::landed);
          continue;
        }
      }
      if (g.drone.return_to_base > 0) errand_step(i, on_base);
    }
    if (on_errand(i) && !(g.drone.battery_capacity > 0 && g.drone.return_to_base > 0))
      drones_.errands.state[i] = static_cast<std::uint8_t>(Errand::none);  // turned off: its behavior flies it again
    if (f.drone_mtbf > 0 && (drones_.fleet.exposure[i] += dt / f.drone_mtbf) >= drones_.fleet.due[i]) {
      ground(i, DroneStatus::failed);
      continue;
    }
    if (f.camera_mtbf > 0 && drones_.fleet.camera[i] && (drones_.fleet.camera_exposure[i] += dt / f.camera_mtbf) >= drones_.fleet.camera_due[i])
      drones_.fleet.camera[i] = 0;
  }
}

void Simulation::ground(std::uint32_t id, DroneStatus status) {
  drones_.status[id] = status;
  drones_.since[id] = time();
  drones_.velocities[id] = drones_.commanded[id] = drones_.steering[id] = {};
  if (wind_active_) drones_.air.velocity[id] = drones_.air.wind[id] = {};
  physics_->disable(id);
  --flying_;
}

const Schema<FailureSetup>& failure_schema() {
  static const Schema<FailureSetup> schema{
      field<&FailureSetup::drone_mtbf>({"drone_mtbf", 0, 0, 1e9, "s", "mean time to failure of a whole drone, its own exponential clock drawn from the seed; 0: never", 0}),
      field<&FailureSetup::camera_mtbf>({"camera_mtbf", 0, 0, 1e9, "s", "mean time to failure of a drone's camera: it flies on, finding nothing; 0: never", 0}),
  };
  return schema;
}

void Simulation::set_failures(const FailureSetup& f) {
  for (const auto& field : failure_schema())
    if (const double v = field.get(f); !field.spec.check(v).empty())
      throw std::invalid_argument("failures." + field.spec.name + ": " + format::number(v) + " s " + field.spec.check(v));
  setup_.failures = f;
}

void Simulation::fail(std::uint32_t id, bool camera_only) {
  if (id >= drones_.positions.size())
    throw std::invalid_argument("drone " + std::to_string(id) + " does not exist (allowed: ids 0 to " +
                                std::to_string(drones_.positions.size() - 1) + ")");
  if (drones_.status[id] != DroneStatus::flying) return;  // down already
  if (!camera_only) ground(id, DroneStatus::failed);
  else if (drones_.fleet.camera[id]) drones_.fleet.camera[id] = 0;
}

void Simulation::fail_fraction(double fraction, bool camera_only) {
  if (!(fraction >= 0 && fraction <= 1))
    throw std::invalid_argument(format::number(fraction) + " is out of range (allowed: a fraction in [0, 1])");
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i)
    if (drones_.status[i] == DroneStatus::flying && (!camera_only || drones_.fleet.camera[i])) candidates.push_back(i);
  // A shuffle from the seed's own stream for this event: the same drones whatever the behavior.
  Rng rng(setup_.seed, first_failure_stream - 1 - fraction_failures_++);
  for (std::size_t k = candidates.size(); k > 1; --k) std::swap(candidates[k - 1], candidates[rng.index(k)]);
  const auto count = static_cast<std::size_t>(std::llround(fraction * static_cast<double>(candidates.size())));
  for (std::size_t k = 0; k < count; ++k) fail(candidates[k], camera_only);
}

void Simulation::Drones::Fleet::columns(std::vector<StateColumn>& out) const {
  out.push_back(StateColumn::of("camera_works", "", "fleet", "1 while its camera works, 0 once the camera failed", camera));
  out.push_back(StateColumn::of("energy_used", "J", "fleet", "energy drawn from its battery so far", used));
  out.push_back(StateColumn::of("battery_left", "J", "fleet", "energy left in its battery (inf without a battery model)", charge));
  out.push_back(StateColumn::of("failure_exposure", "", "fleet", "its failure clock: integral of dt / drone_mtbf so far", exposure));
  out.push_back(StateColumn::of("failure_due", "", "fleet", "the Exp(1) draw its failure clock fails the drone at", due));
  out.push_back(StateColumn::of("camera_failure_exposure", "", "fleet", "its camera's failure clock: integral of dt / camera_mtbf", camera_exposure));
  out.push_back(StateColumn::of("camera_failure_due", "", "fleet", "the Exp(1) draw its camera's clock fails the camera at", camera_due));
}

}  // namespace salsa
