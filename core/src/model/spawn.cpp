// The world a test starts in: the map's geometry, its groups, the targets placed and the drones spawned.
#include "salsa/core/model/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "model/light_world.hpp"
#include "model/physics_world.hpp"
#include "model/plugin_call.hpp"
#include "model/step_parallel.hpp"
#include "model/streams.hpp"
#include "format.hpp"

namespace salsa {

using namespace detail;

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

/// Where a new drone starts: in spawn mode disc a random point of the spawn disc (or, outside the walls,
/// the nearest point inside them, as the paper does), else a random free point of the map; every try
/// bounded, the spawn point itself (checked free) as the last resort.
Vec2 spawn_position(const GroupSetup& g, const Rect& bounds, const StaticGeometry& geometry, Vec2 spawn, std::size_t total,
                    Rng& rng, bool& scarce) {
  const double r = g.drone.radius;
  if (g.spawn_mode == SpawnMode::disc) {
    // The paper's default radius, drones × radius, at most the distance to the map's farthest corner:
    // a wider disc covers no more of the map, it only clamps more drones onto the walls (100,000 drones
    // on a 6 km map would pile up in the corners).
    const double farthest = std::hypot(std::max(spawn.x - bounds.min.x, bounds.max.x - spawn.x),
                                       std::max(spawn.y - bounds.min.y, bounds.max.y - spawn.y));
    const double disc = g.spawn_radius > 0 ? g.spawn_radius : std::min(static_cast<double>(total) * r, farthest);
    Vec2 p;
    for (int tries = 0; tries < 100; ++tries) {
      p = rng.in_disc(spawn, disc);
      if (geometry.is_free(p, r)) return p;
    }
    p = {std::clamp(p.x, bounds.min.x + r, bounds.max.x - r), std::clamp(p.y, bounds.min.y + r, bounds.max.y - r)};
    if (geometry.is_free(p, r)) return p;
  }
  // Free space under 1/10,000 of the map: once a drone found none, the others try briefly.
  for (int tries = 0, most = scarce ? 100 : 10'000; tries < most; ++tries)
    if (Vec2 p = rng.in_rect(bounds); geometry.is_free(p, r)) return p;
  scarce = true;
  return spawn;
}

std::vector<Vec2> ray_directions(int rays) {
  std::vector<Vec2> out;
  for (int k = 0; k < rays; ++k) out.push_back(Vec2::polar(1, 2 * pi * k / rays));
  return out;
}

std::pair<double, double> failure_draws(std::uint64_t seed, std::uint32_t id) {
  Rng rng(seed, first_failure_stream + id);
  const double drone = -std::log1p(-rng.uniform());
  return {drone, -std::log1p(-rng.uniform())};
}

}  // namespace

Simulation::Group Simulation::make_group(const GroupSetup& g, Vec2 base, const TargetKind* kind, bool with_targets) {
  Group out;
  out.properties = drone_properties(g.drone);
  out.base = base;
  out.rays = ray_directions(g.drone.obstacle_rays);
  out.noise = {g.drone.position_noise, g.drone.neighbour_noise, g.drone.obstacle_noise, g.drone.miss_probability,
               g.drone.false_detection_rate};
  if (kind && with_targets) {
    if (auto p = check_view_range(*kind, g.drone)) throw std::invalid_argument(p.text());
    out.reach = plugin_call(target_kind, 0, [&] { return kind->view_range(g.drone.camera_range); });
  }
  return out;
}

std::size_t Simulation::message_size(const Behavior& behavior, std::uint32_t g) {
  const std::size_t size = plugin_call(behavior_kind, g, [&] { return behavior.message_size(); });
  if (size > max_message_size)
    throw PluginFailure(behavior_kind, g, "message_size() is " + std::to_string(size) + " doubles (allowed: at most " +
                                              std::to_string(max_message_size) + ")");
  return size;
}

std::size_t Simulation::ray_slots(const std::vector<Group>& groups) {
  std::size_t most = 0;
  for (const Group& g : groups) most = std::max(most, g.rays.size());
  return most;
}

Simulation::World Simulation::build_world(const SimulationSetup& s, Parallel& parallel) {
  if (auto p = check_map(s.map)) throw std::invalid_argument("map: " + p.text());
  double obstacle_range = 0;
  for (const GroupSetup& g : s.groups) {
    const std::string in = s.groups.size() > 1 ? "groups." + g.name + "." : "";
    if (auto p = check_drone(g.drone, s.dt)) throw std::invalid_argument(in + p.text());
    if (auto p = check_resolution(s.map.bounds, g.drone, s.dt, s.physics)) throw std::invalid_argument(in + "map: " + p.text());
    if (auto p = check_wind(s.wind, g.drone, s.dt)) throw std::invalid_argument(in + p.text());
    check_drone_count(g.drones);
    obstacle_range = std::max(obstacle_range, g.drone.obstacle_range);
  }
  World w;
  w.geometry = StaticGeometry(s.map, std::max(obstacle_range, 1.0));
  // Targets go on the map before any drone exists, so make_setup can check them without spawning; they
  // see the first group's drone properties.
  std::vector<Vec2> targets;
  if (s.target_kind) targets = initial_targets(*s.target_kind, s.targets, s.map, w.geometry, s.groups[0].drone, s.dt, s.seed);
  for (const GroupSetup& g : s.groups) {
    const Vec2 base = g.spawn.value_or(s.map.spawn);
    if (!base.finite() || !w.geometry.is_free(base, g.drone.radius))
      throw std::invalid_argument((s.groups.size() > 1 ? "groups." + g.name + ": " : "") + "spawn point " + format::point(base) +
                                  " is inside an obstacle or outside the map bounds (it needs a free disc of the drone radius)");
    w.groups.push_back(make_group(g, base, s.target_kind.get(), !targets.empty()));
  }
  w.targets = make_targets(std::move(targets), w.groups, s.target_kind.get(), s.seed);
  if (s.physics == PhysicsMode::light) w.physics = std::make_unique<LightWorld>(parallel.arena);
  else w.physics = std::make_unique<PhysicsWorld>(w.geometry);
  w.spawn_rng = Rng(s.seed, spawn_stream);
  for (const DroneModel& m : s.models) w.drones.models.emplace_back(m.name, m.columns);
  for (std::uint32_t g = 0; g < s.groups.size(); ++g)
    w.drones = grown(std::move(w.drones), g, s.groups[g].drones, s, w.geometry, w.groups[g].base, w.spawn_rng, 0);
  w.drones.sensing.hits.assign(w.drones.positions.size() * ray_slots(w.groups), {});
  return w;
}

// `from` and `count` new drones of group `group` after it, spawned at `base` at time `time`, each with
// a fresh Rng stream of its own id and its failure draws.
Simulation::Drones Simulation::grown(Drones d, std::uint32_t group, std::size_t count, const SimulationSetup& s,
                                     const StaticGeometry& geometry, Vec2 base, Rng& spawn_rng, double time) {
  const GroupSetup& g = s.groups[group];
  const std::size_t first = d.positions.size(), n = first + count;
  check_drone_count(n);
  std::size_t total = count;  // the group's drones once these are added: the spawn disc's size
  for (std::size_t i = 0; i < first; ++i) total += d.groups[i] == group && d.status[i] != DroneStatus::removed;
  bool scarce = false;
  for (std::size_t i = first; i < n; ++i) {
    d.positions.push_back(spawn_position(g, s.map.bounds, geometry, base, total, spawn_rng, scarce));
    const double heading = spawn_rng.angle();  // drawn first, as g++ evaluated the call: the order is fixed, not the compiler's
    d.velocities.push_back(Vec2::polar(spawn_rng.uniform(0.1 * g.drone.max_speed, g.drone.max_speed), heading));
    d.rngs.emplace_back(s.seed, first_drone_stream + i);
    const auto [drone, camera] = failure_draws(s.seed, static_cast<std::uint32_t>(i));
    d.fleet.due.push_back(drone);
    d.fleet.camera_due.push_back(camera);
  }
  d.steering.resize(n);
  d.commanded.resize(n);
  d.groups.resize(n, group);
  d.status.resize(n, DroneStatus::flying);
  d.fleet.camera.resize(n, 1);
  d.fleet.used.resize(n, 0.0);
  d.fleet.charge.resize(n, g.drone.battery_capacity > 0 ? g.drone.battery_capacity * 3600 : inf);
  d.since.resize(n, time);
  d.fleet.exposure.resize(n, 0.0);
  d.fleet.camera_exposure.resize(n, 0.0);
  d.sensing.hit_counts.resize(n, 0);
  for (ModelState& m : d.models) m.grow(n);
  return d;
}

Simulation::Targets Simulation::make_targets(std::vector<Vec2> positions, const std::vector<Group>& groups, const TargetKind* kind,
                                             std::uint64_t seed) {
  Targets t;
  double reach = 0;
  for (const Group& g : groups) reach = std::max(reach, g.reach);
  t.states.reserve(positions.size());
  for (Vec2 p : positions) t.states.push_back({p});
  // Cells of the query radius: a query touches 3 × 3 cells whatever the kind's view range.
  t.cell = std::max(reach, 1.0);
  t.grid.build(positions, t.cell);
  if (kind && !positions.empty() && plugin_call(target_kind, 0, [&] { return kind->moves(); })) {
    t.moving = true;
    t.radius = plugin_call(target_kind, 0, [&] { return kind->radius(); });
    t.max_speed = plugin_call(target_kind, 0, [&] { return kind->max_speed(); });
    t.velocities.assign(positions.size(), Vec2{});
    t.positions = std::move(positions);
    t.rng = Rng(seed, target_motion_stream);
  }
  return t;
}

}  // namespace salsa
