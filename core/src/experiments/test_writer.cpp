// Writing a test: the resolved test as config.json holds it (defaults filled in, the plugins' versions), enough to rerun it.
#include "salsa/core/experiments/test_spec.hpp"

#include "salsa/core/experiments/test_models.hpp"
#include "experiments/test_reader.hpp"

namespace salsa {

using detail::handler_params;
using detail::json;

namespace detail {

ParameterValues handler_params(const PluginChoice& c, const PluginHost& host) {
  ParameterValues values(host.contact_handler(c.name).factory.parameters);
  for (const auto& [k, x] : c.params.items()) values.set(k, x);
  return values;
}

}  // namespace detail

namespace {
json params_json(const ParameterValues& v) {
  json out = json::object();
  for (const auto& [k, x] : v.items()) out[k] = x;
  return out;
}
/// A model's section: its fields nested by the dots in their names, {"x", "y"} pairs as [x, y].
json model_json(const TestSpec& t, const TestModel& m) {
  json out = json::object();
  for (const ModelField& f : m.fields) {
    json* at = &out;
    for (std::size_t start = 0, dot; (dot = f.spec.name.find('.', start)) != std::string::npos; start = dot + 1)
      at = &(*at)[f.spec.name.substr(start, dot - start)];
    const double v = f.get(t);
    (*at)[f.spec.name.substr(f.spec.name.rfind('.') + 1)] =
        f.flag ? json(v != 0) : f.spec.is_integer() ? json(static_cast<std::int64_t>(v)) : json(v);
  }
  for (auto& [key, value] : out.items())
    if (value.is_object() && value.size() == 2 && value.contains("x") && value.contains("y")) value = json::array({value["x"], value["y"]});
  return out;
}
template <class Base>
json plugin_json(const Entry<Base>& e) {
  std::error_code ec;  // absolute: config.json is read later, from anywhere
  const fs::path file = fs::absolute(e.plugin().file, ec).lexically_normal();
  return {{"plugin", e.plugin().name}, {"version", e.plugin().version}, {"file", (ec ? e.plugin().file : file).string()},
          {"sha256", e.plugin().sha256}};
}
}  // namespace

std::string resolved_json(const TestSpec& t, const PluginHost& host) {
  json j;
  j["name"] = t.name;
  // A group's fields: at the top level in the single form (as before groups), else in "groups".
  auto group_json = [](const GroupSpec& g, json& out) {
    out["behavior"] = {{"name", g.behavior.name}, {"params", params_json(g.behavior.params)}};
    if (!g.behavior.label.empty()) out["behavior"]["label"] = g.behavior.label;
    out["drone"] = {{"name", g.drone.name}};
    // The energy model's properties matter only with a battery, sensor noise's only when some is not 0:
    // written then (config.json stays as it was without).
    for (const DroneProperty& p : drone_schema())
      if (section_in_use(g.drone, p.section))
        out["drone"][p.spec.name] = p.spec.is_integer() ? json(static_cast<std::int64_t>(p.get(g.drone))) : json(p.get(g.drone));
    out["drones"] = g.drones;
  };
  auto spawn_json = [](const GroupSpec& g) {
    json out = {{"mode", g.spawn_mode == SpawnMode::disc ? "disc" : "uniform"}, {"radius", g.spawn_radius}};
    if (g.spawn) out["point"] = {g.spawn->x, g.spawn->y};
    return out;
  };
  if (t.named_groups) {
    j["groups"] = json::array();
    for (const GroupSpec& g : t.groups) {
      json one = {{"name", g.name}};
      group_json(g, one);
      one["spawn"] = spawn_json(g);
      j["groups"].push_back(one);
    }
  } else {
    group_json(t.groups[0], j);
  }
  for (const TestModel& m : test_models())  // only those in use: a test without one keeps its config.json bytes
    if (m.section && m.in_use(t)) j[m.key] = model_json(t, m);
  if (!t.wind_field.name.empty()) j["wind"]["field"] = {{"name", t.wind_field.name}, {"params", params_json(t.wind_field.params)}};
  j["map"] = {{"name", t.map.name}, {"params", params_json(t.map.params)}};
  if (!t.map_file.empty()) j["map"]["file"] = t.map_file;
  if (!t.named_groups) j["spawn"] = spawn_json(t.groups[0]);
  j["targets"] = {{"kind", t.target.name}, {"count", t.targets}, {"params", params_json(t.target.params)}};
  j["contact_handlers"] = json::array();
  for (const auto& h : t.contact_handlers)
    j["contact_handlers"].push_back({{"name", h.name}, {"params", params_json(handler_params(h, host))}});
  j["metrics"] = json::array();
  for (const auto& m : t.metrics) j["metrics"].push_back({{"name", m.name}, {"params", params_json(m.params)}});
  j["time"] = t.time;
  j["dt"] = t.dt;
  j["log_interval"] = t.log_interval;
  j["velocity_iterations"] = t.velocity_iterations;
  j["position_iterations"] = t.position_iterations;
  j["decision_lag"] = t.decision_lag;
  if (t.physics == PhysicsMode::light) j["physics"] = "light";  // only then: a Box2D test keeps its config.json bytes
  j["seed"] = t.seed;
  j["repeat"] = t.repeat;
  if (!t.condition.empty()) j["condition"] = {{"name", t.condition}, {"label", t.condition_label}};
  if (!t.changes.empty()) {  // only when there are some: earlier tests keep their config.json bytes
    json changes = json::array();
    for (const Change& c : t.changes) {
      const bool whole = change_is_whole(c.key);  // counts read as counts
      changes.push_back({{"time", c.time}, {"set", {{c.key, whole ? json(static_cast<std::uint64_t>(c.value)) : json(c.value)}}}});
    }
    j["changes"] = changes;
  }
  json versions = {{"salsa", salsa_version()}};
  if (t.named_groups) {
    versions["behaviors"] = json::array();
    for (const GroupSpec& g : t.groups) versions["behaviors"].push_back(plugin_json(host.behavior(g.behavior.name)));
  } else {
    versions["behavior"] = plugin_json(host.behavior(t.groups[0].behavior.name));
  }
  versions["map"] = plugin_json(host.map(t.map.name));
  if (t.targets > 0) versions["target"] = plugin_json(host.target_kind(t.target.name));
  json handlers = json::array();
  for (const auto& h : t.contact_handlers) handlers.push_back(plugin_json(host.contact_handler(h.name)));
  versions["contact_handlers"] = handlers;
  json metrics = json::array();
  for (const auto& m : t.metrics) metrics.push_back(plugin_json(host.metric(m.name)));
  versions["metrics"] = metrics;
  if (!t.wind_field.name.empty()) versions["wind"] = plugin_json(host.wind(t.wind_field.name));
  j["versions"] = versions;
  return j.dump(2) + "\n";
}

}  // namespace salsa
