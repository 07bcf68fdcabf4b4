// Live changes: each builds its new state aside (it may throw), then swaps it in (it cannot).
#include "salsa/core/model/simulation.hpp"

#include <algorithm>
#include <limits>

#include "model/physics.hpp"
#include "model/plugin_call.hpp"
#include "model/step_parallel.hpp"
#include "model/world_views.hpp"

namespace salsa {

using namespace detail;

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

}  // namespace

void Simulation::set_drone_count(std::size_t n, std::uint32_t group) {
  check_drone_count(n);
  if (group >= setup_.groups.size()) throw std::invalid_argument("group " + std::to_string(group) + " does not exist");
  std::vector<std::uint32_t> present;  // the group's drones not removed, by id
  std::vector<GroupSetup> counted = setup_.groups;  // every group's drones once this change is made
  for (GroupSetup& g : counted) g.drones = 0;
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i)
    if (drones_.status[i] != DroneStatus::removed) {
      ++counted[drones_.groups[i]].drones;
      if (drones_.groups[i] == group) present.push_back(i);
    }
  counted[group].drones = n;
  // Room for them, as for a test's drones at the start: a pile in which every drone touches every other
  // is refused, not simulated (its contacts grow as n²).
  if (n > present.size())
    if (const Problem p = check_room(setup_.map.bounds, setup_.map.spawn, counted)) throw std::invalid_argument(p.what);
  Rng rng = spawn_rng_;
  Drones next = n > present.size() ? grown(drones_, group, n - present.size(), setup_, geometry_, groups_[group].base, rng, time())
                                   : drones_;
  for (std::size_t k = n; k < present.size(); ++k) {  // the highest ids go
    const std::uint32_t i = present[k];
    next.status[i] = DroneStatus::removed;
    next.since[i] = time();
    next.velocities[i] = next.commanded[i] = next.steering[i] = {};
  }
  next.sensing.hits.resize(next.positions.size() * ray_slots_);
  for (std::uint32_t g = 0; g < setup_.groups.size(); ++g)
    plugin_call(behavior_kind, g, [&] { setup_.groups[g].behavior->resize(next.positions.size()); });
  // Handlers see the drones as they will be (removed ones stay in the spans, with their status).
  std::swap(drones_, next);
  try {
    reset_handlers(*this);
  } catch (...) {
    std::swap(drones_, next);
    throw;
  }
  // Nothing below throws.
  const std::size_t before = next.positions.size();  // the drones before the change (swapped out)
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i) {
    if (i >= before) physics_->add_drone(i, drones_.positions[i], drones_.velocities[i], setup_.groups[group].drone, true);
    else if (drones_.status[i] == DroneStatus::removed) physics_->disable(i);
  }
  flying_ = static_cast<std::size_t>(std::count(drones_.status.begin(), drones_.status.end(), DroneStatus::flying));
  if (wind_active_) track_air();
  sensed_.clear();  // ids may name other drones: whatever is in view next comes into view
  spawn_rng_ = rng;
  setup_.groups[group].drones = n;
  comm_changed();
}

void Simulation::set_drone_config(const DroneConfig& config, std::uint32_t group) {
  if (group >= setup_.groups.size()) throw std::invalid_argument("group " + std::to_string(group) + " does not exist");
  if (auto p = check_drone(config, setup_.dt)) throw std::invalid_argument(p.text());
  if (auto p = check_resolution(setup_.map.bounds, config, setup_.dt, setup_.physics)) throw std::invalid_argument("map: " + p.text());
  if (auto p = check_wind(setup_.wind, config, setup_.dt)) throw std::invalid_argument(p.text());
  SimulationSetup next_setup = setup_;
  next_setup.groups[group].drone = config;
  std::vector<Group> next_groups = groups_;
  const TargetKind* kind = setup_.target_kind.get();
  next_groups[group] = make_group(next_setup.groups[group], groups_[group].base, kind, !targets_.states.empty());
  std::vector<Vec2> points;  // the cameras size the target grid
  points.reserve(targets_.states.size());
  for (const auto& t : targets_.states) points.push_back(t.position);
  Targets regridded = make_targets(std::move(points), next_groups, nullptr, 0);
  // Nothing below throws. A battery keeps its charge as a fraction of the new capacity.
  const double old_capacity = setup_.groups[group].drone.battery_capacity * 3600, capacity = config.battery_capacity * 3600;
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.groups[i] != group) continue;
    // Max speed bounds the air velocity: with wind the ground velocity may exceed it.
    if (wind_active_) drones_.air.velocity[i] = drones_.air.velocity[i].clamped(config.max_speed);
    else drones_.velocities[i] = drones_.velocities[i].clamped(config.max_speed);
    if (capacity != old_capacity)
      drones_.fleet.charge[i] = capacity <= 0 ? inf : old_capacity <= 0 ? capacity : drones_.fleet.charge[i] / old_capacity * capacity;
  }
  setup_ = std::move(next_setup);
  groups_ = std::move(next_groups);
  ray_slots_ = ray_slots(groups_);
  drones_.sensing.hits.assign(drones_.positions.size() * ray_slots_, {});
  grid_range_ = 0;
  for (const GroupSetup& g : setup_.groups) grid_range_ = std::max(grid_range_, g.drone.detection_range);
  targets_.grid = std::move(regridded.grid);
  targets_.cell = regridded.cell;
  for (Sensed& d : sensed_) d.reach = -1;  // their lists are in the old grid's order
  physics_->remove_drones_from(0);
  add_bodies();
}

void Simulation::set_dt(double dt) {
  for (const GroupSetup& g : setup_.groups) {
    if (auto p = check_drone(g.drone, dt)) throw std::invalid_argument(p.text());
    if (auto p = check_resolution(setup_.map.bounds, g.drone, dt, setup_.physics)) throw std::invalid_argument("map: " + p.text());
    if (auto p = check_wind(setup_.wind, g.drone, dt)) throw std::invalid_argument(p.text());
  }
  if (targets_.moving)
    if (auto p = check_target_motion(*setup_.target_kind, dt)) throw std::invalid_argument("targets: " + p.text());
  dt_base_time_ = time();
  dt_base_steps_ = steps_;
  setup_.dt = dt;
}

void Simulation::set_wind(const Wind& wind, std::shared_ptr<WindField> field) {
  for (const GroupSetup& g : setup_.groups)
    if (auto p = check_wind(wind, g.drone, setup_.dt))
      throw std::invalid_argument((setup_.groups.size() > 1 ? "groups." + g.name + ": " : "") + p.text());
  setup_.wind = wind;
  setup_.wind_field = std::move(field);
  if (!wind_active_ && (wind != Wind{} || setup_.wind_field)) {
    wind_active_ = true;  // for good: air velocities are kept from now on, even if the wind drops to zero
    track_air();          // the velocities now are relative to still air
  }
}

void Simulation::set_behavior(std::shared_ptr<Behavior> behavior, std::uint32_t group) {
  if (!behavior) throw std::invalid_argument("behavior: none given");
  if (group >= setup_.groups.size()) throw std::invalid_argument("group " + std::to_string(group) + " does not exist");
  behavior->group_ = group;
  const std::size_t size = message_size(*behavior, group);
  plugin_call(behavior_kind, group, [&] { behavior->reset(drones_.positions.size()); });
  setup_.groups[group].behavior = std::move(behavior);
  message_sizes_[group] = size;
  comm_changed();
}

void Simulation::set_map(const MapData& map, std::optional<Vec2> spawn) {
  SimulationSetup next = setup_;
  next.map = map;
  next.groups[0].spawn = spawn;
  for (std::uint32_t g = 0; g < next.groups.size(); ++g) {  // each group as many as it has now
    next.groups[g].drones = 0;
    for (std::uint32_t i = 0; i < drones_.positions.size(); ++i)
      next.groups[g].drones += drones_.groups[i] == g && drones_.status[i] != DroneStatus::removed;
  }
  World world = build_world(next, *parallel_);
  for (std::uint32_t g = 0; g < next.groups.size(); ++g)
    plugin_call(behavior_kind, g, [&] { next.groups[g].behavior->reset(world.drones.positions.size()); });
  StateView view(next.map, world.geometry, world.groups[0].properties, time(), next.dt, world.drones.positions,
                 world.drones.velocities, world.drones.groups, world.drones.status);
  reset_handlers(view);
  // Nothing below throws.
  setup_ = std::move(next);
  install(std::move(world));
}

void Simulation::set_targets(std::shared_ptr<TargetKind> kind, std::size_t count) {
  std::vector<Vec2> positions;
  if (kind) positions = initial_targets(*kind, count, setup_.map, geometry_, setup_.groups[0].drone, setup_.dt, setup_.seed);
  std::vector<Group> next_groups;
  for (std::uint32_t g = 0; g < setup_.groups.size(); ++g)
    next_groups.push_back(make_group(setup_.groups[g], groups_[g].base, kind.get(), !positions.empty()));
  Targets next = make_targets(std::move(positions), next_groups, kind.get(), setup_.seed);
  reset_handlers(*this);  // what a handler sees of the world (no targets) is as it will be
  // Nothing below throws.
  targets_ = std::move(next);
  sensed_.clear();  // new targets: whatever is in view next comes into view
  groups_ = std::move(next_groups);
  setup_.target_kind = std::move(kind);
  setup_.targets = count;
}

}  // namespace salsa
