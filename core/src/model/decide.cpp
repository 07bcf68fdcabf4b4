// Decide: what each drone perceives (its Perception) and its behavior's decision.
#include "salsa/core/model/simulation.hpp"

#include "salsa/core/model/batch_behavior.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "model/plugin_call.hpp"
#include "model/step_parallel.hpp"
#include "model/noise.hpp"

namespace salsa {

using namespace detail;

Perception Simulation::perceive(std::uint32_t id, Senses senses, Scratch& s) const {
  const std::uint32_t g = drones_.groups[id];
  const DroneProperties& cfg = groups_[g].properties;
  const Vec2 p = drones_.positions[id];
  s.neighbours.clear();
  // One search of the drone grid serves the neighbours and the messages' candidate senders (comm's
  // reach may pass the detection range: then neighbours are those within it, in the same order).
  const double detection = senses.neighbours ? cfg.detection_range : 0, reach = setup_.comm.on ? comm_reach_ : 0;
  s.hits.clear();
  if (detection > 0 || reach > 0) drone_grid_.gather(p, std::max(detection, reach), s.hits);
  if (senses.neighbours) {
    const double within = reach > detection ? detection * detection : std::numeric_limits<double>::infinity();
    // The common case, every drone flying in one group, reads neither status nor group per neighbour.
    if (flying_ == drones_.positions.size() && groups_.size() == 1) {
      for (const auto& [j, d2] : s.hits)
        if (j != id && d2 < within) s.neighbours.push_back({drones_.positions[j], drones_.velocities[j], std::sqrt(d2), j, 0});
    } else {
      for (const auto& [j, d2] : s.hits)
        if (j != id && d2 < within && drones_.status[j] == DroneStatus::flying)
          s.neighbours.push_back({drones_.positions[j], drones_.velocities[j], std::sqrt(d2), j, drones_.groups[j]});
    }
  }
  const GroupSetup& group = setup_.groups[g];
  Perception me;
  me.id = id;
  me.position = p;
  me.velocity = drones_.velocities[id];
  me.air_velocity = wind_active_ ? drones_.air.velocity[id] : drones_.velocities[id];
  if (wind_active_) me.wind = drones_.air.wind[id];
  me.max_speed = cfg.max_speed;
  me.max_force = cfg.max_force;
  me.radius = cfg.radius;
  me.mass = cfg.mass;
  me.camera_range = cfg.camera_range;
  me.obstacle_range = cfg.obstacle_range;
  me.detection_range = cfg.detection_range;
  me.dt = setup_.dt;
  me.time = time();
  me.group = g;
  me.base = groups_[g].base;
  me.battery_capacity = group.drone.battery_capacity;
  me.battery = me.battery_capacity > 0 ? std::clamp(drones_.fleet.charge[id] / (me.battery_capacity * 3600), 0.0, 1.0) : 1.0;
  me.neighbours = s.neighbours;
  me.obstacles = {drones_.sensing.hits.data() + id * ray_slots_, drones_.sensing.hit_counts[id]};
  s.targets.clear();
  if (senses.targets) {
    s.targets.assign(sensed_[id].seen.begin(), sensed_[id].seen.end());
    for (TargetSeen& t : s.targets) t.found = targets_.states[t.id].found();
  }
  me.targets = s.targets;
  me.world = this;
  if (setup_.comm.on) {
    comm_->receive(steps_, id, setup_.comm, setup_.seed, drones_.groups, geometry_, s.hits, s.senders, s.messages, comm_counts_[id]);
    me.messages = s.messages;
    me.outbox = &comm_->outbox(id);
  } else {
    s.outbox = {{s.room.data(), message_sizes_[g]}, 0, false};
    me.outbox = &s.outbox;
  }
  return me;
}

// Decide: each group's behavior's shared state first (serial, in group order), then every flying drone
// in parallel, each perceiving only what its behavior senses. Each drone writes only its own steering
// slot and uses its own Rng stream, so any thread count gives the same result. A group whose behavior
// decides in batches (batch_behavior.hpp) is left out of the parallel part and decided after it, once
// for the whole group (decide_batch.cpp). A drone on a return-to-base errand is steered by the core.
void Simulation::decide() {
  std::array<Senses, 1> one{};
  std::array<BatchBehavior*, 1> one_batch{};
  std::vector<Senses> many;
  std::vector<BatchBehavior*> many_batch;
  std::span<Senses> senses = one;
  std::span<BatchBehavior*> batch = one_batch;
  if (setup_.groups.size() > 1) {
    many.resize(setup_.groups.size()), senses = many;
    many_batch.resize(setup_.groups.size()), batch = many_batch;
  }
  bool batches = false;
  for (std::uint32_t g = 0; g < setup_.groups.size(); ++g) {
    Behavior& behavior = *setup_.groups[g].behavior;
    plugin_call(behavior_kind, g, [&] { behavior.prepare(*this); });
    senses[g] = plugin_call(behavior_kind, g, [&] { return behavior.senses(); });
    batch[g] = dynamic_cast<BatchBehavior*>(&behavior);
    batches = batches || batch[g];
  }
  // Asked once per step, so that without noise a drone's perception costs one test of a local more.
  bool noise = false;
  for (const Group& g : groups_) noise = noise || g.noise.perceived() || g.noise.false_rate > 0;
  if (setup_.comm.on && (comm_stale_ || comm_counts_.size() != drones_.positions.size())) {
    comm_->resize(drones_.positions.size(), message_sizes_, drones_.groups, setup_.comm.latency);
    comm_stale_ = false;
  }
  if (setup_.comm.on) {
    comm_counts_.assign(drones_.positions.size(), {});
    comm_reach_ = comm_->reach(steps_, drones_.positions, setup_.comm.range);
  }
  parallel_->for_each(drone_grid_.cell_order(), [&](std::uint32_t i, Scratch& s) {
    if (drones_.status[i] != DroneStatus::flying) return;
    const std::uint32_t g = drones_.groups[i];
    const bool away = on_errand(i);  // the core flies it (return_to_base.cpp), not its behavior
    if (batches && batch[g] && !away) return;
    Behavior& behavior = *setup_.groups[g].behavior;
    Perception me = perceive(i, senses[g], s);
    if (noise) add_noise(me, senses[g], s);
    drones_.steering[i] = away ? errand_steering(me) : plugin_call(behavior_kind, g, [&] { return behavior.decide(me, drones_.rngs[i]); });
  });
  if (batches)
    for (std::uint32_t g = 0; g < setup_.groups.size(); ++g)
      if (batch[g]) decide_batch(g, *batch[g], senses[g], noise);
}

}  // namespace salsa
