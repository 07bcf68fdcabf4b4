// What pairs a queue's tests: the world key and its paired seed, and the variant the comparison sets apart on each world.
#include "salsa/core/experiments/queue.hpp"

#include "experiments/fnv1a.hpp"
#include "experiments/test_reader.hpp"
#include "format.hpp"

namespace salsa {

using detail::fnv1a64;

namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// Parameter values as a JSON object; nlohmann::json (not ordered_json) sorts its keys.
nlohmann::json sorted_params(const ParameterValues& values) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [name, value] : values.items()) out[name] = value;
  return out;
}

}  // namespace

std::uint64_t paired_seed(std::uint64_t queue_seed, std::size_t repeat, const std::string& world_key) {
  constexpr std::uint64_t json_exact = (std::uint64_t{1} << 53) - 1;
  return splitmix64(fnv1a64(world_key) ^ splitmix64(queue_seed ^ splitmix64(repeat))) & json_exact;
}

std::string world_key(const TestSpec& t) {
  nlohmann::json key;
  key["map"] = {{"name", t.map.name}, {"params", sorted_params(t.map.params)}};
  // The file's name only: the same map reached from another working folder is the same world.
  if (!t.map_file.empty()) key["map"]["file"] = fs::path(t.map_file).filename().string();
  // A group's part: its spawn, the drone properties that shape the world and its count; the single
  // form's at the top level, as before groups.
  auto group_key = [](const GroupSpec& g, nlohmann::json& out) {
    out["spawn"] = {{"mode", g.spawn_mode == SpawnMode::disc ? "disc" : "uniform"}, {"radius", g.spawn_radius}};
    if (g.spawn) out["spawn"]["point"] = {g.spawn->x, g.spawn->y};
    out["drone"] = nlohmann::json::object();
    for (const DroneProperty& p : drone_schema())
      if (p.shapes_world)
        out["drone"][p.spec.name] = p.spec.is_integer() ? nlohmann::json(static_cast<int>(p.get(g.drone))) : nlohmann::json(p.get(g.drone));
    out["drones"] = g.drones;
  };
  if (t.groups.size() > 1) {
    key["groups"] = nlohmann::json::array();
    for (const GroupSpec& g : t.groups) {
      nlohmann::json one = {{"name", g.name}};
      group_key(g, one);
      key["groups"].push_back(one);
    }
  } else {
    group_key(t.groups[0], key);
  }
  key["targets"] = {{"count", t.targets}};
  if (t.targets > 0) {
    key["targets"]["kind"] = t.target.name;
    key["targets"]["params"] = sorted_params(t.target.params);
  }
  return key.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string describe_choice(const PluginChoice& choice, const Parameters& schema) {
  std::string changed;
  for (const Parameter& p : schema)
    if (choice.params.has(p.name) && choice.params.get(p.name) != p.value)
      changed += (changed.empty() ? "" : " ") + p.name + "=" + format::number(choice.params.get(p.name));
  return changed.empty() ? choice.name : choice.name + "(" + changed + ")";
}

std::string variant_label(const std::string& behavior, const std::vector<std::pair<std::string, std::string>>& changed) {
  if (changed.empty()) return behavior + " (defaults)";
  std::string out = behavior + ":";
  for (std::size_t i = 0; i < changed.size(); ++i) out += (i ? ", " : " ") + changed[i].first + " = " + changed[i].second;
  return out;
}

std::string variant(const TestSpec& t, const PluginHost& host) {
  auto one = [&](const PluginChoice& b) {
    if (!b.label.empty()) return b.label;
    std::vector<std::pair<std::string, std::string>> changed;
    for (const Parameter& p : host.behavior(b.name).factory.parameters)
      if (b.params.has(p.name) && b.params.get(p.name) != p.value) changed.emplace_back(p.name, format::number(b.params.get(p.name)));
    return variant_label(b.name, changed);
  };
  if (t.groups.size() == 1) return one(t.groups[0].behavior);
  std::string out;  // "scouts=flocking (defaults) / base=random_walk: speed = 2"
  for (const GroupSpec& g : t.groups) out += (out.empty() ? "" : " / ") + g.name + "=" + one(g.behavior);
  return out;
}

}  // namespace salsa
