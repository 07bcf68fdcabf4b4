#include "salsa/core/experiments/test_spec.hpp"

#include "salsa/core/files/format.hpp"

#include <cmath>
#include <cstdio>
#include <tuple>
#include <unordered_map>

#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/run/metrics.hpp"
#include "salsa/core/files/names.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "experiments/test_reader.hpp"

namespace salsa {

using detail::json;
using detail::num;
using detail::Reader;
using detail::show;

const char* salsa_version() { return SALSA_VERSION; }

std::size_t TestSpec::steps() const { return static_cast<std::size_t>(std::llround(time / dt)); }
std::size_t TestSpec::log_every() const {
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(log_interval / dt)));
}
std::size_t TestSpec::drone_total() const {
  std::size_t n = 0;
  for (const GroupSpec& g : groups) n += g.drones;
  return n;
}
int TestSpec::group_index(std::string_view wanted) const {
  for (std::size_t g = 0; g < groups.size(); ++g)
    if (groups[g].name == wanted) return static_cast<int>(g);
  return -1;
}
bool TestSpec::fleet() const {
  if (groups.size() > 1 || failures != FailureSetup{}) return true;
  for (const GroupSpec& g : groups)
    if (g.drone.battery_capacity > 0) return true;
  for (const Change& c : changes)
    if (c.key.starts_with("fail") || (c.key.ends_with("battery_capacity") && c.value > 0)) return true;
  return false;
}

namespace detail {

json read_json_file(const std::filesystem::path& file, std::string_view expected) {
  try {
    return strict_json::read_file<json>(file, expected);
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
}
namespace {
json parse_json(const std::string& text, const std::string& where) {
  try {
    return strict_json::parse<json>(text, where);
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
}
}  // namespace

DroneConfig parse_drone(const json& v, const Reader& r, const std::vector<DroneConfig>& named, const std::string& at) {
  auto by_name = [&](const std::string& name, const std::string& field) {
    for (const auto& c : named)
      if (c.name == name) return c;
    std::string list;
    for (const auto& c : named) list += (list.empty() ? "" : ", ") + c.name;
    r.fail(field, "unknown drone configuration '" + strict_json::printable(name) + "' (known: " + list + ")");
  };
  if (v.is_string()) return by_name(v.get<std::string>(), at);
  if (!v.is_object()) r.fail(at, show(v) + " must be an object");
  for (const auto& [key, value] : v.items())  // "name", "base" and the schema's properties
    if (key != "name" && key != "base" && !drone_schema().find(key))
      r.fail(Reader::join(at, key), "unknown key (allowed: name, base, " + drone_schema().names() + ")");
  DroneConfig d = v.contains("base") ? by_name(r.string(v["base"], at + ".base"), at + ".base") : DroneConfig{};
  d.name = v.contains("name") ? r.string(v["name"], at + ".name") : (v.contains("base") ? d.name + "-custom" : "custom");
  for (const DroneProperty& p : drone_schema()) {
    const Parameter& s = p.spec;
    if (!v.contains(s.name)) continue;
    const std::string field = at + "." + s.name;
    p.set(d, s.is_integer() ? static_cast<double>(r.integer(v[s.name], field, s.min, s.max))
                            : r.number(v[s.name], field, s.min, s.max, s.unit.c_str()));
  }
  return d;
}

std::vector<DroneConfig> drone_configs_file(const std::filesystem::path& file) {
  const json j = read_json_file(file, "an object of named drone configurations, {\"heavy\": {\"max_speed\": 6}}");
  const Reader fr(strict_json::printable(file.string(), 200), file.parent_path());
  if (!j.is_object()) fr.fail("(top level)", show(j) + " must be an object of named drone configurations");
  std::vector<DroneConfig> out = builtin_drone_configs();
  for (const auto& [name, v] : j.items()) {
    json copy = v;
    if (!copy.is_object()) fr.fail(Reader::join("", name), show(v) + " must be an object");
    copy["name"] = name;
    out.push_back(parse_drone(copy, fr, out, Reader::join("", name)));
  }
  return out;
}

namespace {
Vec2 point(const json& v, const Reader& r, const std::string& field) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    r.fail(field, show(v) + " must be a point [x, y] in m");
  return {v[0].get<double>(), v[1].get<double>()};
}

/// A plugin choice at `field`: "name" or {"name": ..., "params": {...}}; the params unchecked yet.
std::pair<std::string, json> name_and_params(const json& v, const Reader& r, const std::string& field) {
  if (!v.is_object()) return {r.string(v, field), json()};
  r.only_keys(v, field, {"name", "params"});
  if (!v.contains("name")) r.fail(field + ".name", "missing");
  return {r.string(v["name"], field + ".name"), v.value("params", json())};
}

}  // namespace

namespace {

/// "wind": {"velocity": [x, y], "gusts": {"strength", "time_scale"}, "field": "name" | {"name", "params"}},
/// each number as wind_schema() declares it. "velocity" may also be {"x": ..., "y": ...} (either left
/// out: 0): the form sweep.set's wind.velocity.x fills in.
void parse_wind(TestSpec& t, const json& w, const Reader& r, const PluginHost& host) {
  r.only_keys(w, "wind", {"velocity", "gusts", "field"});
  auto set = [&](const json& v, const std::string& name) {
    const WindProperty& p = *wind_schema().find(name);
    p.set(t.wind, r.number(v, "wind." + name, p.spec.min, p.spec.max, p.spec.unit.c_str()));
  };
  if (w.contains("velocity")) {
    const json& v = w["velocity"];
    if (v.is_object()) {
      r.only_keys(v, "wind.velocity", {"x", "y"});
      for (const char* axis : {"x", "y"})
        if (v.contains(axis)) set(v[axis], std::string("velocity.") + axis);
    } else if (v.is_array() && v.size() == 2) {
      set(v[0], "velocity.x");
      set(v[1], "velocity.y");
    } else {
      r.fail("wind.velocity", show(v) + " must be a velocity [x, y] in m/s (or {\"x\": ..., \"y\": ...})");
    }
  }
  if (w.contains("gusts")) {
    const json& g = w["gusts"];
    r.only_keys(g, "wind.gusts", {"strength", "time_scale"});
    for (const char* key : {"strength", "time_scale"})
      if (g.contains(key)) set(g[key], std::string("gusts.") + key);
  }
  if (w.contains("field")) {
    json params;
    std::tie(t.wind_field.name, params) = name_and_params(w["field"], r, "wind.field");
    try {
      t.wind_field.params = r.params(params, "wind.field.params", host.wind(t.wind_field.name).factory.parameters,
                                     "wind '" + t.wind_field.name + "'");
    } catch (const UnknownPlugin& e) {
      r.fail("wind.field", e.what());
    }
  }
}

SpawnMode spawn_mode(const json& v, const Reader& r, const std::string& field) {
  const std::string mode = r.string(v, field);
  if (mode == "disc") return SpawnMode::disc;
  if (mode == "uniform") return SpawnMode::uniform;
  r.fail(field, show(v) + " is not a spawn mode (allowed: disc, uniform)");
}

/// A group's fields, from the test's top level (at "") or from one of its "groups" (at "groups[1]").
void parse_group(GroupSpec& g, const json& j, const Reader& r, const PluginHost& host, const std::vector<DroneConfig>& named,
                 const std::string& at) {
  // behavior: "name" or {"name": ..., "params": {...}}
  const std::string behavior = Reader::join(at, "behavior");
  if (!j.contains("behavior")) r.fail(behavior, "missing (e.g. \"behavior\": \"flocking\")");
  json params;
  std::tie(g.behavior.name, params) = name_and_params(j["behavior"], r, behavior);
  try {
    const auto& e = host.behavior(g.behavior.name);
    g.behavior.params = r.params(params, behavior + ".params", e.factory.parameters, "behavior '" + g.behavior.name + "'");
  } catch (const UnknownPlugin& e) {
    r.fail(behavior, e.what());
  }
  if (j.contains("drone")) g.drone = parse_drone(j["drone"], r, named, Reader::join(at, "drone"));
  if (j.contains("drones")) g.drones = r.integer(j["drones"], Reader::join(at, "drones"), 1, 1'000'000);
  if (j.contains("spawn")) {
    const std::string field = Reader::join(at, "spawn");
    const json& s = j["spawn"];
    r.only_keys(s, field, {"mode", "point", "radius"});
    if (s.contains("mode")) g.spawn_mode = spawn_mode(s["mode"], r, field + ".mode");
    if (s.contains("point")) g.spawn = point(s["point"], r, field + ".point");
    if (s.contains("radius")) g.spawn_radius = r.number(s["radius"], field + ".radius", 0, 1e7, "m");
  }
}

}  // namespace

CommSetup parse_comm(const json& c, const Reader& r) {
  if (!c.is_object()) r.fail("comm", show(c) + " must be an object, e.g. {\"range\": 100, \"loss\": 0.1}");
  for (const auto& [key, value] : c.items())
    if (!comm_schema().find(key)) r.fail(Reader::join("comm", key), "unknown key (allowed: " + comm_schema().names() + ")");
  CommSetup out;
  out.on = true;
  for (const CommField& f : comm_schema()) {
    if (!c.contains(f.spec.name)) continue;
    const std::string field = "comm." + f.spec.name;
    const json& v = c[f.spec.name];
    if (f.flag) {  // true or false; 0 and 1 too, as a sweep or a timed change gives them
      if (v.is_boolean()) f.set(out, v.get<bool>() ? 1 : 0);
      else if (v.is_number() && (v.get<double>() == 0 || v.get<double>() == 1)) f.set(out, v.get<double>());
      else r.fail(field, show(v) + " is not true or false (allowed: true, false, 1, 0)");
    } else {
      f.set(out, f.spec.is_integer() ? static_cast<double>(r.integer(v, field, f.spec.min, f.spec.max))
                                     : r.number(v, field, f.spec.min, f.spec.max, f.spec.unit.c_str()));
    }
  }
  return out;
}

TestSpec parse_test(const json& j, const Reader& r, const PluginHost& host) {
  r.only_keys(j, "", test_keys);
  TestSpec t;
  if (j.contains("name")) {
    t.name = r.string(j["name"], "name");
    if (const std::string why = test_name_problem(t.name); !why.empty()) r.fail("name", why);
  }

  std::vector<DroneConfig> named = builtin_drone_configs();
  if (j.contains("drone_configs")) named = drone_configs_file(r.path(j["drone_configs"], "drone_configs"));
  if (j.contains("groups")) {
    // [{"name": "surveyors", "drones": 10, "drone": "large", "behavior": ..., "spawn": {...}}, ...]
    for (const char* key : {"behavior", "drone", "drones", "spawn"})
      if (j.contains(key)) r.fail(key, std::string("given beside \"groups\" (allowed: one or the other; each group has its own ") + key + ")");
    const json& list = j["groups"];
    if (!list.is_array() || list.empty())
      r.fail("groups", show(list) + " must be a non-empty list of groups, e.g. [{\"name\": \"scouts\", \"drones\": 10, \"behavior\": \"flocking\"}]");
    t.groups.assign(list.size(), {});
    t.named_groups = true;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = "groups[" + std::to_string(i) + "]";
      r.only_keys(list[i], at, {"name", "behavior", "drone", "drones", "spawn"});
      GroupSpec& g = t.groups[i];
      if (!list[i].contains("name")) r.fail(at + ".name", "missing (each group has a name, used in the outputs' columns)");
      g.name = r.string(list[i]["name"], at + ".name");
      if (const std::string why = name_problem(g.name); !why.empty()) r.fail(at + ".name", why);
      if (g.name.find('.') != std::string::npos)
        r.fail(at + ".name", show(list[i]["name"]) + " has a dot (allowed: letters, digits, '_' and '-'; keys such as groups.<name>.drones split at dots)");
      if (const int k = t.group_index(g.name); k >= 0 && static_cast<std::size_t>(k) < i)
        r.fail(at + ".name", "'" + g.name + "' is also groups[" + std::to_string(k) + "]'s name (allowed: each name once)");
      parse_group(g, list[i], r, host, named, at);
    }
  } else {
    parse_group(t.groups[0], j, r, host, named, "");
  }
  if (j.contains("comm")) t.comm = parse_comm(j["comm"], r);
  if (j.contains("failures")) {
    const json& f = j["failures"];
    r.only_keys(f, "failures", {"drone_mtbf", "camera_mtbf"});
    if (f.contains("drone_mtbf")) t.failures.drone_mtbf = r.number(f["drone_mtbf"], "failures.drone_mtbf", 0, 1e9, "s");
    if (f.contains("camera_mtbf")) t.failures.camera_mtbf = r.number(f["camera_mtbf"], "failures.camera_mtbf", 0, 1e9, "s");
  }
  if (j.contains("wind")) parse_wind(t, j["wind"], r, host);

  // map: "name" | "file.json" | {"name", "params", "file"}
  {
    json m = j.value("map", json("empty"));
    json params;
    if (m.is_string() && m.get<std::string>().ends_with(".json")) m = json{{"file", m}};
    if (m.is_object()) {
      r.only_keys(m, "map", {"name", "params", "file"});
      t.map.name = m.contains("name") ? r.string(m["name"], "map.name") : (m.contains("file") ? "json" : "");
      if (t.map.name.empty()) r.fail("map", "needs a \"name\" or a \"file\"");
      if (m.contains("file")) t.map_file = r.path(m["file"], "map.file").string();
      params = m.value("params", json());
    } else {
      t.map.name = r.string(m, "map");
    }
    try {
      const auto& e = host.map(t.map.name);
      t.map.params = r.params(params, "map.params", e.factory.parameters, "map '" + t.map.name + "'");
    } catch (const UnknownPlugin& e) {
      r.fail("map", e.what());
    }
  }

  // targets: {"kind": "tree", "count": 100, "params": {...}}
  {
    const json tg = j.value("targets", json::object());
    r.only_keys(tg, "targets", {"kind", "count", "params"});
    t.target.name = tg.contains("kind") ? r.string(tg["kind"], "targets.kind") : "tree";
    if (tg.contains("count")) t.targets = r.integer(tg["count"], "targets.count", 0, 10'000'000);
    try {
      const auto& e = host.target_kind(t.target.name);
      t.target.params = r.params(tg.value("params", json()), "targets.params", e.factory.parameters,
                                 "target kind '" + t.target.name + "'");
    } catch (const UnknownPlugin& e) {
      if (t.targets > 0 || tg.contains("kind")) r.fail("targets.kind", e.what());
    }
  }

  // contact_handlers: ["name", {"name": ..., "params": {...}}, ...], called in this order; absent: the
  // default list (detect_targets), with its declared defaults.
  {
    const bool given = j.contains("contact_handlers");
    const json h = given ? j["contact_handlers"] : json::array();
    if (!h.is_array()) r.fail("contact_handlers", show(h) + " must be a list of handler names or {\"name\", \"params\"} objects");
    if (given) t.contact_handlers.assign(h.size(), {});
    for (std::size_t i = 0; i < t.contact_handlers.size(); ++i) {
      const std::string field = "contact_handlers[" + std::to_string(i) + "]";
      PluginChoice& c = t.contact_handlers[i];
      json params;  // none for the default list: its declared defaults
      if (given) std::tie(c.name, params) = name_and_params(h[i], r, field);
      try {
        c.params = r.params(params, field + ".params", host.contact_handler(c.name).factory.parameters,
                            "contact handler '" + c.name + "'");
      } catch (const UnknownPlugin& e) {
        r.fail(field, e.what());
      }
    }
  }

  // metrics: ["name", {"name": ..., "params": {...}}, ...]; absent: the built-in ones
  if (j.contains("metrics")) {
    const json& m = j["metrics"];
    if (!m.is_array()) r.fail("metrics", show(m) + " must be a list of metric names or {\"name\", \"params\"} objects");
    for (std::size_t i = 0; i < m.size(); ++i) {
      const std::string field = "metrics[" + std::to_string(i) + "]";
      PluginChoice c;
      json params;
      std::tie(c.name, params) = name_and_params(m[i], r, field);
      try {
        c.params = r.params(params, field + ".params", host.metric(c.name).factory.parameters, "metric '" + c.name + "'");
      } catch (const UnknownPlugin& e) {
        r.fail(field, e.what());
      }
      t.metrics.push_back(std::move(c));
    }
  } else {
    for (const char* name : default_metrics)
      if (std::any_of(host.metrics().begin(), host.metrics().end(), [&](const auto& e) { return e.factory.name == name; }))
        t.metrics.push_back({name, ParameterValues(host.metric(name).factory.parameters)});
  }
  try {
    MetricSet(t.metrics, host);  // columns that clash, metrics that cannot be made
  } catch (const MetricListError& e) {
    r.fail("metrics[" + std::to_string(e.index) + "]", e.what());
  }

  if (j.contains("dt")) t.dt = r.number(j["dt"], "dt", 1e-4, 1, "s");
  if (j.contains("time")) t.time = r.number(j["time"], "time", t.dt, 1e7, "s");
  if (j.contains("log_interval")) t.log_interval = r.number(j["log_interval"], "log_interval", t.dt, 1e7, "s");
  if (j.contains("velocity_iterations")) t.velocity_iterations = static_cast<int>(r.integer(j["velocity_iterations"], "velocity_iterations", 1, 100));
  if (j.contains("position_iterations")) t.position_iterations = static_cast<int>(r.integer(j["position_iterations"], "position_iterations", 1, 100));
  if (j.contains("decision_lag")) t.decision_lag = static_cast<int>(r.integer(j["decision_lag"], "decision_lag", 0, 1));
  if (j.contains("physics")) {
    const json& p = j["physics"];
    if (p == "box2d") t.physics = PhysicsMode::box2d;
    else if (p == "light") t.physics = PhysicsMode::light;
    else r.fail("physics", show(p) + " is not a physics (allowed: box2d, light)");
  }
  if (j.contains("repeat")) t.repeat = r.integer(j["repeat"], "repeat", 0, 1'000'000);
  if (j.contains("condition")) {
    const json& c = j["condition"];
    r.only_keys(c, "condition", {"name", "label"});
    t.condition = r.string(c.value("name", json()), "condition.name");
    if (c.contains("label") && !c["label"].is_string()) r.fail("condition.label", show(c["label"]) + " must be a string");
    t.condition_label = c.value("label", "");
  }
  t.seed_given = j.contains("seed");
  t.seed = t.seed_given ? r.integer(j["seed"], "seed", 0, 9007199254740992.0) : paired_seed(1, t.repeat, world_key(t));

  // changes: [{"time": 30, "set": {"behavior.params.cohesion_weight": 2, "drones": 20}}, ...], each
  // checked against the test as the earlier ones left it.
  if (j.contains("changes")) {
    const json& list = j["changes"];
    if (!list.is_array()) r.fail("changes", show(list) + " must be a list of {\"time\", \"set\"} objects");
    TestSpec state = t;
    double last = 0;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string field = "changes[" + std::to_string(i) + "]";
      r.only_keys(list[i], field, {"time", "set"});
      if (!list[i].contains("time")) r.fail(field + ".time", "missing");
      if (!list[i].contains("set")) r.fail(field + ".set", "missing");
      const double time = r.number(list[i]["time"], field + ".time", last, t.time, "s");
      const json& set = list[i]["set"];
      if (!set.is_object() || set.empty()) r.fail(field + ".set", show(set) + " must be an object of key: value");
      for (const auto& item : set.items()) {
        const std::string at = field + ".set." + strict_json::printable(item.key());
        if (!item.value().is_number()) r.fail(at, show(item.value()) + " is not a number");
        const Change c{time, item.key(), item.value().get<double>()};
        if (const std::string why = check_change(state, c, host); !why.empty()) r.fail(at, why);
        apply_to_test(state, c);
        t.changes.push_back(c);
      }
      last = time;
    }
  }
  return t;
}

}  // namespace detail

TestSpec parse_test(const std::string& json_text, const std::string& where, const PluginHost& host,
                    const std::filesystem::path& base_dir) {
  TestSpec t = detail::parse_test(detail::parse_json(json_text, where), Reader(where, base_dir), host);
  t.source = where;
  if (t.name.empty()) t.name = "test";
  return t;
}

namespace {
json params_json(const ParameterValues& v) {
  json out = json::object();
  for (const auto& [k, x] : v.items()) out[k] = x;
  return out;
}
/// A contact handler's values over its declared defaults (a TestSpec made in code may give none).
ParameterValues handler_params(const PluginChoice& c, const PluginHost& host) {
  ParameterValues values(host.contact_handler(c.name).factory.parameters);
  for (const auto& [k, x] : c.params.items()) values.set(k, x);
  return values;
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
  if (t.failures != FailureSetup{}) j["failures"] = {{"drone_mtbf", t.failures.drone_mtbf}, {"camera_mtbf", t.failures.camera_mtbf}};
  if (t.comm.on) {  // only then: a test without it keeps its config.json bytes
    json comm = json::object();
    for (const CommField& f : comm_schema())
      comm[f.spec.name] = f.flag ? json(f.get(t.comm) != 0) : f.spec.is_integer() ? json(static_cast<std::int64_t>(f.get(t.comm))) : json(f.get(t.comm));
    j["comm"] = comm;
  }
  if (t.has_wind()) {  // only then: a test without wind keeps its config.json bytes
    j["wind"] = {{"velocity", {t.wind.velocity.x, t.wind.velocity.y}},
                 {"gusts", {{"strength", t.wind.gust_strength}, {"time_scale", t.wind.gust_time_scale}}}};
    if (!t.wind_field.name.empty()) j["wind"]["field"] = {{"name", t.wind_field.name}, {"params", params_json(t.wind_field.params)}};
  }
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

  // The map: what the plugin made is input too, checked like a map file (the simulation relies on
  // the same map rules whoever made the map).
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
  if (const Problem p = check_map(s.map)) throw InputError(t.source + ": " + provider("map", *map_entry) + " returned " + p.text());
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
      throw InputError(t.source + ": " + (g.spawn ? in(g) + "spawn.point" : in(g) + map_name) + ": spawn point [" + num(spawn.x) + ", " +
                       num(spawn.y) + "] is inside an obstacle or outside the bounds (allowed: free space, at least the drone radius " +
                       num(g.drone.radius) + " m from any wall)");
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

std::optional<std::pair<std::size_t, std::size_t>> first_same_test(const std::vector<const TestSpec*>& tests) {
  // Fields that any two same tests share; equal hashes are then compared field by field.
  auto key = [](const TestSpec& t) {
    std::size_t h = std::hash<std::uint64_t>{}(t.seed);
    auto mix = [&h](std::size_t v) { h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2); };
    auto mix_double = [&](double v) { mix(std::hash<double>{}(v == 0 ? 0.0 : v)); };  // -0 == 0, as == says
    mix(t.drone_total()), mix(t.targets), mix(t.repeat);
    mix_double(t.time), mix_double(t.dt);
    std::vector<const PluginChoice*> choices{&t.map, &t.target};
    for (const GroupSpec& g : t.groups) choices.push_back(&g.behavior);
    for (const PluginChoice* c : choices) {
      mix(std::hash<std::string>{}(c->name));
      for (const auto& [name, value] : c->params.items()) mix_double(value);
    }
    mix(std::hash<std::string>{}(t.map_file));
    return h;
  };
  auto same = [](const TestSpec& a, const TestSpec& b) {
    TestSpec x = a;
    x.name = b.name, x.source = b.source, x.seed_given = b.seed_given;
    return x == b;
  };
  std::unordered_multimap<std::size_t, std::size_t> seen;
  seen.reserve(tests.size());
  for (std::size_t j = 0; j < tests.size(); ++j) {
    const std::size_t k = key(*tests[j]);
    for (auto [it, end] = seen.equal_range(k); it != end; ++it)
      if (same(*tests[it->second], *tests[j])) return std::pair{it->second, j};
    seen.emplace(k, j);
  }
  return std::nullopt;
}

namespace {
using format::grouped;
constexpr auto sig = format::significant;
}  // namespace

std::string workload_warning(const TestSpec& t, const SimulationSetup& s) {
  // Wall time per drone-step on one core, measured with flocking (docs/architecture.md): about 1 µs,
  // plus 0.01 µs per neighbour (each is gathered, and the behavior looks at it).
  constexpr double per_drone_step = 1e-6, per_neighbour = 1e-8;
  const Rect& b = s.map.bounds;
  double free_area = b.area();
  for (const Polyline& poly : s.map.obstacles) {
    double twice = 0;  // shoelace
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) twice += poly[j].cross(poly[i]);
    free_area -= std::abs(twice) / 2;
  }
  free_area = std::max(free_area, b.area() / 100);
  auto neighbours_of = [&](double drones, double range) { return std::min(drones - 1, drones * pi * range * range / free_area); };
  // The timed changes may raise the drone count or the detection range: the test costs the sum of its
  // stretches, and the message describes its heaviest one.
  TestSpec now = t;
  double seconds = 0, heaviest = -1, drones = 0, range = 0, neighbours = 0;
  std::uint64_t from = 0;
  auto stretch = [&](std::uint64_t to) {
    double r = 0;
    for (const GroupSpec& g : now.groups) r = std::max(r, g.drone.detection_range);
    const double n = static_cast<double>(now.drone_total()), k = neighbours_of(n, r);
    const double per_step = n * (per_drone_step + per_neighbour * k);
    seconds += static_cast<double>(to - std::min(from, to)) * per_step;
    if (per_step > heaviest) heaviest = per_step, drones = n, range = r, neighbours = k;
    from = std::max(from, to);
  };
  const std::uint64_t steps = t.steps();
  for (const Change& c : t.changes) {
    const std::uint64_t at = std::min<std::uint64_t>(change_step(c.time, t.dt), steps);
    if (at > from) stretch(at);
    if (at >= steps) break;  // after the end: never applied
    apply_to_test(now, c);
  }
  stretch(steps);
  const double steps_per_second = 1 / t.dt;
  if (seconds < 3600) return {};
  const double hours = seconds / 3600;
  double first_range = 0;
  for (const GroupSpec& g : t.groups) first_range = std::max(first_range, g.drone.detection_range);
  const bool changed = drones != static_cast<double>(t.drone_total()) || range != first_range;
  return t.source + ": " + grouped(drones) + " drones" + (changed ? " (after its timed changes)" : "") + " with detection range " +
         sig(range, 6) + " m on a " + sig(b.width(), 6) + " m × " + sig(b.height(), 6) + " m map: ~" + grouped(neighbours) +
         " neighbours per drone, about " + sig(drones * neighbours * steps_per_second, 2) + " drone-neighbour checks per simulated second; " +
         sig(t.time, 6) + " s simulated: expect " +
         (hours < 48 ? "hours (about " + sig(hours, 2) + " h" : "days (about " + sig(hours / 24, 2) + " days") + " on one core)";
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
  if (const Problem p = check_map(map)) throw InputError(file.string() + ": " + p.text());  // before a grid is sized from it
  if (!StaticGeometry(map, 50).is_free(map.spawn, drone_radius))
    throw InputError(file.string() + ": spawn: [" + num(map.spawn.x) + ", " + num(map.spawn.y) +
                     "] is inside an obstacle or outside the bounds (allowed: free space, at least " + num(drone_radius) +
                     " m from any wall)");
  return map;
}

}  // namespace salsa
