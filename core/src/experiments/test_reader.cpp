// Reading a test: a test object, drone configurations and their files, strict JSON; one-line errors for bad input.
#include "salsa/core/experiments/test_spec.hpp"

#include <tuple>

#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/experiments/metric_list.hpp"
#include "salsa/core/files/names.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "experiments/test_reader.hpp"

namespace salsa {

using detail::Reader;

namespace detail {

std::vector<const char*> test_keys() {
  std::vector<const char*> keys{"name", "behavior", "drone", "drone_configs", "drones", "groups"};
  for (const TestModel& m : test_models())
    if (m.section) keys.push_back(m.key.c_str());
  for (const char* k : {"map", "spawn", "targets", "contact_handlers", "metrics", "time", "dt", "log_interval", "velocity_iterations",
                        "position_iterations", "decision_lag", "physics", "seed", "repeat", "changes", "condition", "versions", "archive"})
    keys.push_back(k);
  return keys;
}

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

/// A plugin choice at `field`: "name" or {"name": ..., "params": {...}} (a behavior's may have a
/// "label" too, read apart); the params unchecked yet.
std::pair<std::string, json> name_and_params(const json& v, const Reader& r, const std::string& field, bool labelled = false) {
  if (!v.is_object()) return {r.string(v, field), json()};
  if (labelled) r.only_keys(v, field, {"name", "params", "label"});
  else r.only_keys(v, field, {"name", "params"});
  if (!v.contains("name")) r.fail(field + ".name", "missing");
  return {r.string(v["name"], field + ".name"), v.value("params", json())};
}

}  // namespace

namespace {

/// The wind's field ("field": "name" | {"name", "params"}); its numbers are a model's (test_models.hpp).
void parse_wind_field(TestSpec& t, const json& w, const Reader& r, const PluginHost& host) {
  json params;
  std::tie(t.wind_field.name, params) = name_and_params(w, r, "wind.field");
  try {
    t.wind_field.params = r.params(params, "wind.field.params", host.wind(t.wind_field.name).factory.parameters,
                                   "wind '" + t.wind_field.name + "'");
  } catch (const UnknownPlugin& e) {
    r.fail("wind.field", e.what());
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
  std::tie(g.behavior.name, params) = name_and_params(j["behavior"], r, behavior, true);
  if (j["behavior"].contains("label")) g.behavior.label = r.label(j["behavior"]["label"], behavior + ".label");
  try {
    const auto& e = host.behavior(g.behavior.name);
    g.behavior.params = r.params(params, behavior + ".params", e.factory.parameters, "behavior '" + g.behavior.name + "'");
  } catch (const UnknownPlugin& e) {
    r.fail(behavior, e.what());
  }
  if (j.contains("drone")) g.drone = parse_drone(j["drone"], r, named, Reader::join(at, "drone"));
  if (j.contains("drones")) g.drones = r.integer(j["drones"], Reader::join(at, "drones"), 1, max_test_drones);
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

void parse_model(TestSpec& t, const TestModel& m, const json& section, const Reader& r) {
  // The section's keys: each field's first part ("gusts" of "gusts.strength"), then those read elsewhere.
  std::vector<std::string> keys;
  for (const ModelField& f : m.fields)
    if (const std::string first = f.spec.name.substr(0, f.spec.name.find('.')); std::find(keys.begin(), keys.end(), first) == keys.end())
      keys.push_back(first);
  keys.insert(keys.end(), m.other_keys.begin(), m.other_keys.end());
  std::vector<const char*> allowed;
  for (const std::string& k : keys) allowed.push_back(k.c_str());
  r.only_keys(section, m.key, allowed);
  auto read = [&](const ModelField& f, const json& v, const std::string& field) {
    if (f.flag) {  // true or false; 0 and 1 too, as a sweep or a timed change gives them
      if (v.is_boolean()) f.set(t, v.get<bool>() ? 1 : 0);
      else if (v.is_number() && (v.get<double>() == 0 || v.get<double>() == 1)) f.set(t, v.get<double>());
      else r.fail(field, show(v) + " is not true or false (allowed: true, false, 1, 0)");
    } else {
      f.set(t, f.spec.is_integer() ? static_cast<double>(r.integer(v, field, f.spec.min, f.spec.max))
                                   : r.number(v, field, f.spec.min, f.spec.max, f.spec.unit.c_str()));
    }
  };
  for (const std::string& k : keys) {
    if (!section.contains(k) || std::find(m.other_keys.begin(), m.other_keys.end(), k) != m.other_keys.end()) continue;
    const std::string at = m.key + "." + k;
    if (const ModelField* f = m.find(k)) {
      read(*f, section[k], at);
      continue;
    }
    // A nested object ({"strength": ..., "time_scale": ...}); x and y also as a vector [x, y].
    const ModelField* x = m.find(k + ".x");
    const ModelField* y = m.find(k + ".y");
    const json& v = section[k];
    if (x && y && v.is_array()) {
      if (v.size() != 2) r.fail(at, show(v) + " must be [x, y] in " + x->spec.unit + " (or {\"x\": ..., \"y\": ...})");
      read(*x, v[0], at + ".x");
      read(*y, v[1], at + ".y");
      continue;
    }
    if (x && y && !v.is_object()) r.fail(at, show(v) + " must be [x, y] in " + x->spec.unit + " (or {\"x\": ..., \"y\": ...})");
    std::vector<std::string> inner;
    for (const ModelField& f : m.fields)
      if (f.spec.name.starts_with(k + ".")) inner.push_back(f.spec.name.substr(k.size() + 1));
    std::vector<const char*> inner_allowed;
    for (const std::string& i : inner) inner_allowed.push_back(i.c_str());
    r.only_keys(v, at, inner_allowed);
    for (const std::string& i : inner)
      if (v.contains(i)) read(*m.find(k + "." + i), v[i], at + "." + i);
  }
  if (m.given) m.given(t);
}

TestSpec parse_test(const json& j, const Reader& r, const PluginHost& host) {
  r.only_keys(j, "", test_keys());
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
      if (const std::string why = group_name_problem(g.name); !why.empty()) r.fail(at + ".name", why);
      if (const int k = t.group_index(g.name); k >= 0 && static_cast<std::size_t>(k) < i)
        r.fail(at + ".name", "'" + g.name + "' is also groups[" + std::to_string(k) + "]'s name (allowed: each name once)");
      parse_group(g, list[i], r, host, named, at);
    }
    if (const std::size_t total = t.drone_total(); total > max_test_drones)
      r.fail("groups", std::to_string(total) + " drones in " + std::to_string(t.groups.size()) + " groups (allowed: at most " +
                           std::to_string(max_test_drones) + " drones in a test, over all its groups)");
  } else {
    parse_group(t.groups[0], j, r, host, named, "");
  }
  for (const TestModel& m : test_models())
    if (m.section && j.contains(m.key)) parse_model(t, m, j[m.key], r);
  if (j.contains("wind") && j["wind"].contains("field")) parse_wind_field(t, j["wind"]["field"], r, host);

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
    make_metrics(t.metrics, host);  // columns that clash, metrics that cannot be made
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
  if (j.contains("archive")) {
    if (!j["archive"].is_boolean()) r.fail("archive", show(j["archive"]) + " is not true or false");
    t.archive = j["archive"].get<bool>();
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
  t.seed = t.seed_given ? r.integer(j["seed"], "seed", 0, static_cast<double>(max_seed)) : paired_seed(1, t.repeat, world_key(t));

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

}  // namespace salsa
