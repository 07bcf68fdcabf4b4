// A simulation's construction, its installed state, and the sequence of phases of one step.
#include "salsa/core/model/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <string>

#include "model/plugin_call.hpp"
#include "model/step_parallel.hpp"

namespace salsa {

using namespace detail;

PluginFailure::PluginFailure(std::string kind_, std::size_t index_, const std::string& message)
    : std::runtime_error([&] {
        std::string line = message;  // one line, whatever the plugin wrote
        for (char& c : line)
          if (c == '\n' || c == '\r') c = ' ';
        return line;
      }()),
      kind(std::move(kind_)),
      index(index_) {}


Simulation::Simulation(SimulationSetup setup)
    : setup_(std::move(setup)), parallel_(std::make_unique<Parallel>(setup_.threads)), comm_(std::make_unique<CommState>()) {
  if (setup_.groups.empty()) throw std::invalid_argument("groups: none given");
  for (const GroupSetup& g : setup_.groups)
    if (!g.behavior) throw std::invalid_argument("behavior: none given");
  if (setup_.log_every == 0) setup_.log_every = 1;
  if (const std::string why = comm_problem(setup_.comm); !why.empty()) throw std::invalid_argument(why);
  World world = build_world(setup_, *parallel_);
  for (std::uint32_t g = 0; g < setup_.groups.size(); ++g) {
    Behavior& b = *setup_.groups[g].behavior;
    b.group_ = g;
    message_sizes_.push_back(message_size(b, g));
    plugin_call(behavior_kind, g, [&] { b.reset(world.drones.positions.size()); });
  }
  install(std::move(world));
  gusts_ = Gusts(setup_.seed, setup_.wind.gust_strength);
  if (setup_.wind != Wind{} || setup_.wind_field) {
    wind_active_ = true;
    track_air();
  }
  reset_handlers(*this);
}

Simulation::~Simulation() = default;

void Simulation::reset_handlers(const WorldView& world) const {
  for (std::size_t k = 0; k < setup_.contact_handlers.size(); ++k)
    plugin_call(handler_kind, k, [&] { setup_.contact_handlers[k]->reset(world); });
}

void Simulation::install(World&& w) noexcept {
  geometry_ = std::move(w.geometry);
  groups_ = std::move(w.groups);
  ray_slots_ = ray_slots(groups_);
  grid_range_ = 0;
  for (const GroupSetup& g : setup_.groups) grid_range_ = std::max(grid_range_, g.drone.detection_range);
  physics_ = std::move(w.physics);
  spawn_rng_ = w.spawn_rng;
  drones_ = std::move(w.drones);
  targets_ = std::move(w.targets);
  flying_ = static_cast<std::size_t>(std::count(drones_.status.begin(), drones_.status.end(), DroneStatus::flying));
  physics_->remove_drones_from(0);
  add_bodies();
  sensed_.clear();             // new drones and targets: whatever is in view next comes into view
  if (comm_) comm_->clear();  // new drones: nothing in flight reaches them
  comm_changed();
  if (wind_active_) track_air();  // the new drones' air velocities: their velocities as spawned
}

void Simulation::add_bodies() {
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i)
    physics_->add_drone(i, drones_.positions[i], drones_.velocities[i], setup_.groups[drones_.groups[i]].drone,
                        drones_.status[i] == DroneStatus::flying);
}

// ---------------------------------------------------------------- one step

void Simulation::timed(Phase phase, const auto& fn) {
  if (!setup_.profile) return fn();
  const auto start = std::chrono::steady_clock::now();
  fn();
  profile_[static_cast<std::size_t>(phase)] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Simulation::step() {
  run_models(ModelPhase::start);
  if (wind_active_) timed(Phase::act, [this] { sample_wind(); });
  // The drones' side of a step: sense, decide and report what they saw, all on the snapshot of
  // positions the step started from.
  auto think = [this] {
    timed(Phase::sense, [this] { sense(); });
    timed(Phase::decide, [this] { decide(); });
    if (setup_.comm.on) timed(Phase::communicate, [this] { communicate(); });
  };
  auto report = [this] { timed(Phase::detect, [this] { dispatch_sightings(); }); };
  auto step_physics = [this] { timed(Phase::physics, [this] { physics(); }); };
  // While the physics steps, the other side runs: nothing one writes is read by the other (the physics
  // owns its bodies until read_back).
  if (setup_.decision_lag == 0) {
    think();
    timed(Phase::act, [this] { act(); });
    parallel_->overlap(drones_.positions.size(), step_physics, report);
  } else {
    timed(Phase::act, [this] { act(); });  // last step's decisions
    parallel_->overlap(drones_.positions.size(), step_physics, [&] { think(), report(); });
  }
  if (targets_.moving) timed(Phase::physics, [this] { move_targets(); });  // the targets' step, once nothing reads them
  ++steps_;
  read_back();
  timed(Phase::fleet, [this] { fleet(); });
  run_models(ModelPhase::moved);
  timed(Phase::detect, [this] { dispatch_contacts(); });
  timed(Phase::observe, [this] { observe(); });
}

void Simulation::observe() {
  if (steps_ % setup_.log_every != 0) return;
  for (Observer* o : observers_) o->observe(*this);
}

}  // namespace salsa
