// From a test to a simulation's setup: plugins created, the map made and checked, spawns and targets placed; map files.
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/experiments/test_models.hpp"

#include "experiments/test_reader.hpp"
#include "salsa/core/model/map_check.hpp"
#include "format.hpp"

namespace salsa {

using detail::handler_params;
using detail::json;

namespace {
/// "map 'forest' (plugin basic_maps, /usr/lib/salsa/plugins/libbasic_maps.so)": whose data it is.
template <class Base>
std::string provider(const char* kind, const Entry<Base>& e) {
  return std::string(kind) + " '" + e.factory.name + "' (plugin " + e.plugin().name + ", " + e.plugin().file.string() + ")";
}
}  // namespace

SimulationSetup make_setup(const TestSpec& t, const PluginHost& host, int threads) {
  SimulationSetup s;
  const Entry<MapGenerator>* map_entry = nullptr;
  std::shared_ptr<MapGenerator> map;
  s.groups.clear();
  try {
    map_entry = &host.map(t.map.name);
    map = PluginHost::create(*map_entry, t.map.params);
    for (const GroupSpec& g : t.groups)
      s.groups.push_back({g.name, g.drone, g.drones, PluginHost::create(host.behavior(g.behavior.name), g.behavior.params), g.spawn,
                          g.spawn_mode, g.spawn_radius});
    if (t.targets > 0) s.target_kind = PluginHost::create(host.target_kind(t.target.name), t.target.params);
    for (const auto& h : t.contact_handlers)
      s.contact_handlers.push_back(PluginHost::create(host.contact_handler(h.name), handler_params(h, host)));
    if (!t.wind_field.name.empty()) s.wind_field = PluginHost::create(host.wind(t.wind_field.name), t.wind_field.params);
  } catch (const std::exception& e) {
    throw InputError(t.source + ": " + e.what());
  }
  // A change the behavior's configure() refuses would end the run at its time: refuse it now.
  if (const std::string why = refused_change(t, host); !why.empty()) throw InputError(t.source + ": " + why);
  s.failures = t.failures;
  s.wind = t.wind;
  s.comm = t.comm;
  for (const TestModel& m : test_models())
    if (m.simulate && m.in_use && m.in_use(t)) s.models.push_back(m.simulate(t));
  s.targets = t.targets;
  s.dt = t.dt;
  s.velocity_iterations = t.velocity_iterations;
  s.position_iterations = t.position_iterations;
  s.decision_lag = t.decision_lag;
  s.physics = t.physics;
  s.seed = t.seed;
  s.threads = threads;
  s.log_every = t.log_every();
  // A group's field in messages: "drone.max_speed" in the single form, "groups.scouts.drone.max_speed" with groups.
  auto in = [&](const GroupSpec& g) { return t.named_groups ? "groups." + g.name + "." : std::string(); };
  for (const GroupSpec& g : t.groups)
    if (const Problem p = check_drone(g.drone, t.dt)) throw InputError(t.source + ": " + in(g) + p.text());
  for (const GroupSpec& g : t.groups)
    if (const Problem p = check_wind(t.wind, g.drone, t.dt)) throw InputError(t.source + ": " + p.text() + (t.named_groups ? " (group " + g.name + ")" : ""));

  // The map: what the plugin made is input too. A map file meets the rules of a drawn map, in the words
  // the map creator uses (map_check.hpp), naming the file; a plugin's map what the simulation needs.
  try {
    Rng map_rng(t.seed, 0);
    s.map = map->generate(t.map_file, map_rng);
  } catch (const std::exception& e) {  // MapError too: the map file's own errors already name the file
    std::string why = e.what();
    for (char& c : why)
      if (c == '\n' || c == '\r') c = ' ';
    if (!t.map_file.empty() && why.find(t.map_file) != std::string::npos) throw InputError(t.source + ": " + why);
    throw InputError(t.source + ": " + provider("map", *map_entry) + " failed: " + why);
  }
  if (!t.map_file.empty()) {
    if (const auto problems = map_problems(s.map, 0, MapRules::drawing, 1); !problems.empty())
      throw InputError(t.source + ": " + t.map_file + ": " + problems[0].field + ": " + problems[0].message);
  } else if (const Problem p = check_map(s.map)) {
    throw InputError(t.source + ": " + provider("map", *map_entry) + " returned " + p.text());
  }
  const std::string map_name = t.map_file.empty() ? "map '" + t.map.name + "'" : "map " + t.map_file;
  double obstacle_range = 0;
  for (const GroupSpec& g : t.groups) {
    if (const Problem p = check_resolution(s.map.bounds, g.drone, t.dt, t.physics)) throw InputError(t.source + ": " + in(g) + map_name + ": " + p.text());
    obstacle_range = std::max(obstacle_range, g.drone.obstacle_range);
  }

  // Each group's spawn point must be free before anything is built on it.
  const StaticGeometry geometry(s.map, std::max(obstacle_range, 1.0));
  for (const GroupSpec& g : t.groups) {
    const Vec2 spawn = g.spawn.value_or(s.map.spawn);
    if (!geometry.is_free(spawn, g.drone.radius))
      throw InputError(t.source + ": " + (g.spawn ? in(g) + "spawn.point" : in(g) + map_name) + ": spawn point [" + format::number(spawn.x) + ", " +
                       format::number(spawn.y) + "] is inside an obstacle or outside the bounds (allowed: free space, at least the drone radius " +
                       format::number(g.drone.radius) + " m from any wall)");
  }

  // Room for the drones: on the map, and in the discs they spawn in.
  if (const Problem p = check_room(s.map.bounds, s.map.spawn, s.groups)) {
    const bool pile = p.field == "spawn.radius";
    const std::string field = !pile ? (t.named_groups ? "groups" : "drones") : t.named_groups ? "groups" : "spawn.radius";
    throw InputError(t.source + ": " + field + ": " + (pile ? "" : map_name + ": ") + p.what);
  }

  // The targets, placed as the simulation will place them: the kind's radius and positions are input too.
  if (s.target_kind) {
    try {
      initial_targets(*s.target_kind, t.targets, s.map, geometry, t.groups[0].drone, t.dt, t.seed);
      for (const GroupSpec& g : t.groups)
        if (const Problem p = check_view_range(*s.target_kind, g.drone)) throw std::invalid_argument(p.text());
    } catch (const std::exception& e) {
      throw InputError(t.source + ": " + provider("target kind", host.target_kind(t.target.name)) + ": " + e.what());
    }
  }
  return s;
}

bool is_map_file(const std::filesystem::path& file) {
  try {
    const json j = strict_json::read_file<json>(file, "");
    // A map file missing its bounds is still a map file (so the error says "bounds: missing").
    return j.is_object() && (j.contains("bounds") || (!j.contains("behavior") && !j.contains("tests") &&
                                                      (j.contains("obstacles") || j.contains("hollow") || j.contains("lines"))));
  } catch (const strict_json::Error&) {
    return false;  // read as a test file then, which reports the problem
  }
}

MapData load_map_file(const std::filesystem::path& file, const PluginHost& host, double drone_radius) {
  MapData map;
  try {
    auto generator = PluginHost::create(host.map("json"), ParameterValues(host.map("json").factory.parameters));
    Rng rng(0, 0);
    map = generator->generate(file.string(), rng);
  } catch (const MapError& e) {
    throw InputError(e.what());
  } catch (const std::exception& e) {
    throw InputError(file.string() + ": " + e.what());
  }
  // The map rules a drawn or saved map meets (map_check.hpp), the map creator's and `salsa validate`'s alike.
  if (const auto problems = map_problems(map, drone_radius, MapRules::drawing, 1); !problems.empty())
    throw InputError(file.string() + ": " + problems[0].field + ": " + problems[0].message);
  return map;
}

}  // namespace salsa
