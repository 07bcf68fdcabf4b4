// A queue's "sweep": its axes read as values and checked against the base and conditions, before anything is multiplied out.
#include "format.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_set>

#include "salsa/core/experiments/queue.hpp"
#include "experiments/queue_reader.hpp"

namespace salsa::detail {

namespace {

using format::grouped;

/// from + i × step, on the coarsest decimal grid within its rounding error (an ulp or two): a range in steps of 0.1 gives
/// 0.3, not 0.30000000000000004 (the float noise would show in names and config.json).
double grid_value(double from, double i, double step) {
  const double x = from + i * step;
  const double tolerance = std::numeric_limits<double>::epsilon() * (std::fabs(from) + std::fabs(i * step));
  double scale = 1;
  for (int digits = 0; digits <= 17 && std::fabs(x) * scale < 1e17; ++digits, scale *= 10) {
    const double y = std::round(x * scale) / scale;
    if (std::fabs(y - x) <= tolerance) return y;
  }
  return x;
}

/// {"from", "to", "step"} or {"from", "to", "count"}: both ends included. With a step, an end the
/// float steps miss by a hair (1e-9 of a step) is still reached.
std::vector<double> range_values(const json& v, const std::string& field, const Reader& r) {
  const std::string forms = " (allowed: {\"from\", \"to\", \"step\"} or {\"from\", \"to\", \"count\"})";
  r.only_keys(v, field, {"from", "to", "step", "count"});
  if (!v.contains("from") || !v.contains("to") || v.contains("step") == v.contains("count"))
    r.fail(field, show(v) + " needs \"from\", \"to\" and either \"step\" or \"count\"" + forms);
  for (const char* key : {"from", "to", "step"})
    if (v.contains(key) && !v[key].is_number()) r.fail(field + "." + key, show(v[key]) + " is not a number" + forms);
  const double from = v["from"].get<double>(), to = v["to"].get<double>();
  if (to < from) r.fail(field + ".to", show(v["to"]) + " is below \"from\" " + format::number(from) + " (allowed: to ≥ from)");
  std::vector<double> out;
  if (v.contains("step")) {
    const double step = v["step"].get<double>();
    if (!(step > 0)) r.fail(field + ".step", show(v["step"]) + " is not positive (allowed: a step > 0)");
    const double steps = (to - from) / step;
    if (!(steps < static_cast<double>(max_queue_tests)))
      r.fail(field, show(v) + " gives " + grouped(std::floor(steps) + 1) + " values (allowed: at most " +
                        grouped(max_queue_tests) + " in one range)");
    const double whole = std::round(steps);
    const bool reaches_to = std::fabs(steps - whole) <= 1e-9 * std::max(1.0, steps);
    const auto n = static_cast<std::size_t>(reaches_to ? whole : std::floor(steps)) + 1;
    for (std::size_t i = 0; i < n; ++i)
      out.push_back(reaches_to && i + 1 == n ? to : grid_value(from, static_cast<double>(i), step));
  } else {
    const auto count = static_cast<std::size_t>(r.integer(v["count"], field + ".count", 1, max_queue_tests));
    if (count == 1 && from != to)
      r.fail(field + ".count", "1 gives one value, but \"from\" " + format::number(from) + " and \"to\" " + format::number(to) +
                                   " differ (allowed: a count ≥ 2, or from = to)");
    const double step = count > 1 ? (to - from) / static_cast<double>(count - 1) : 0;
    for (std::size_t i = 0; i < count; ++i)
      out.push_back(i + 1 == count ? to : grid_value(from, static_cast<double>(i), step));
  }
  return out;
}

/// What a swept number allows, for messages: one value ("[0, 10]"), and the axis when it is empty.
struct Allowed {
  std::string value, empty;
};

/// The values of one swept number: a number, a list of numbers or a range, each once and each passing
/// `check` ("" or why it is not allowed).
template <class Check>
std::vector<double> swept_numbers(const json& v, const std::string& field, const Reader& r, const Allowed& allowed, Check check) {
  std::vector<double> out;
  std::unordered_set<double> seen;  // a list or range may hold 10^6 values: no scan per value
  auto add = [&](double x, const std::string& at, const std::string& shown) {
    if (const std::string why = check(x); !why.empty()) r.fail(at, shown + " " + why);
    if (!seen.insert(x == 0 ? 0.0 : x).second) r.fail(at, shown + " is already in the list (allowed: each value once)");
    out.push_back(x);
  };
  if (v.is_number()) {
    add(v.get<double>(), field, show(v));
  } else if (v.is_array()) {
    if (v.empty()) r.fail(field, "[] is an empty list (allowed: " + allowed.empty + ")");
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string at = field + "[" + std::to_string(i) + "]";
      if (!v[i].is_number()) r.fail(at, show(v[i]) + " is not a number (allowed: " + allowed.value + ")");
      add(v[i].get<double>(), at, show(v[i]));
    }
  } else if (v.is_object()) {
    for (const double x : range_values(v, field, r)) add(x, field, show(v) + " gives " + format::number(x) + ", which");
  } else {
    r.fail(field, show(v) + " is not a number, a list of numbers or a range {\"from\", \"to\", \"step\" or \"count\"} (allowed: " +
                      allowed.value + ")");
  }
  return out;
}

/// The values a sweep gives one parameter, each checked against the declared range (and whole numbers).
std::vector<double> param_values(const json& v, const std::string& field, const Parameter& p, const Reader& r) {
  return swept_numbers(v, field, r, {p.range(), "values in " + p.range() + "; or leave the parameter out"},
                       [&](double x) { return p.check(x); });
}

/// sweep.set, checked against sweep.test and the other axes: one axis per key, in key order.
std::vector<std::vector<Point>> set_axes(const json& set, const json& s, const json& base, const json& own, const Reader& r) {
  if (!set.is_object() || set.empty())
    r.fail("sweep.set", show(set) + " must be an object of keys and their values, e.g. {\"drone.max_speed\": [5, 10], "
                                    "\"groups.scouts.drones\": {\"from\": 2, \"to\": 8, \"step\": 2}}");
  std::vector<std::string> keys;
  for (const auto& item : set.items()) keys.push_back(item.key());
  std::sort(keys.begin(), keys.end());  // names and order do not depend on how the file orders the keys
  auto within = [](const std::string& key, const std::string& outer) { return key == outer || key.starts_with(outer + "."); };

  // A key is swept once, and its path must lead to a number of the test.
  const std::pair<const char*, const char*> axes[] = {{"behaviors", "behavior"}, {"maps", "map"}, {"drones", "drones"}, {"targets", "targets"}, {"drone", "drone"}};
  json trial = base;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::string& key = keys[k];
    const std::string field = Reader::join("sweep.set", key);
    check_key(key, field, r);
    for (const auto& [axis, owns] : axes)
      if (s.contains(axis) && within(key, owns)) r.fail(field, std::string("also swept by sweep.") + axis + " (allowed: one or the other)");
    for (std::size_t o = 0; o < k; ++o)  // sorted: an enclosing key comes first
      if (within(key, keys[o])) r.fail(field, "inside sweep.set." + keys[o] + ", also swept (allowed: one or the other)");
    static const char* const single_form[] = {"behavior", "drone", "drones", "spawn"};
    if (base.contains("groups") && base["groups"].is_array() && std::ranges::count(single_form, key_parts(key)[0]))
      r.fail(field, "sweep.test has \"groups\", each with its own (allowed: groups.<name>." + key + ", <name> one of: " + entry_names(base["groups"]) + ")");
    json& leaf = place(trial, key, r, field, "sweep.test");
    if (leaf.is_number())
      r.fail(Reader::join(own.contains(key_parts(key)[0]) ? "sweep.test" : "base", key), "also swept by " + field + " (allowed: one or the other)");
    if (!leaf.is_null()) r.fail(field, "sweep.test." + key + " is " + show(leaf) + ", not a number (allowed: " + set_key_forms + ")");
  }

  // How a key shows in names: its last part ("max_speed15"), or as many more as tell it from the others ("scouts.drones10").
  auto suffix = [](const std::string& key, std::size_t n) {
    const std::vector<std::string> parts = key_parts(key);
    std::string out;
    for (std::size_t i = parts.size() > n ? parts.size() - n : 0; i < parts.size(); ++i) out += (out.empty() ? "" : ".") + parts[i];
    return out;
  };
  std::vector<std::vector<Point>> out;
  for (const std::string& key : keys) {
    std::size_t n = 1;
    while (std::ranges::any_of(keys, [&](const std::string& other) { return other != key && suffix(other, n) == suffix(key, n); })) ++n;
    const std::string label = name_safe(suffix(key, n));
    const std::vector<double> values = swept_numbers(set[key], Reader::join("sweep.set", key), r,
                                                     {"numbers", "at least one number; or leave the key out"},
                                                     [](double) { return std::string(); });  // ranges: the test reader's
    std::vector<Point>& axis = out.emplace_back();
    for (std::size_t i = 0; i < values.size(); ++i)
      axis.push_back({{{key, as_json(values[i])}}, label + number_token(values[i]), "set." + key + "[" + std::to_string(i) + "]"});
  }
  return out;
}

const json& list_axis(const json& v, const std::string& field, const Reader& r, const char* example) {
  if (!v.is_array()) r.fail(field, show(v) + " must be a list, e.g. " + example);
  if (v.empty()) r.fail(field, "[] is an empty list (allowed: at least one entry, e.g. " + std::string(example) + "; or leave the axis out)");
  return v;
}

/// The behaviors or maps axis. `lookup(name)` gives the plugin's declared parameters or throws UnknownPlugin.
template <class Lookup>
std::vector<SweptPlugin> plugin_axis(const json& axis, const std::string& field, const Reader& r, bool maps, Lookup lookup) {
  const char* example = maps ? "[\"empty\", {\"name\": \"forest\", \"params\": {\"clusters\": [10, 20]}}, \"maps/x.json\"]"
                             : "[\"random_walk\", {\"name\": \"flocking\", \"params\": {\"cohesion_weight\": [1, 2]}}]";
  std::vector<SweptPlugin> out;
  for (std::size_t i = 0; const json& item : list_axis(axis, field, r, example)) {
    const std::string at = field + "[" + std::to_string(i++) + "]";
    SweptPlugin e;
    e.at = at.substr(std::string("sweep.").size());
    json given = item;
    if (maps && item.is_string() && item.get<std::string>().ends_with(".json")) given = json{{"file", item}};
    if (given.is_string()) given = json{{"name", given}};
    if (!given.is_object()) r.fail(at, show(item) + " must be a name or an object {\"name\", \"params\"}");
    if (maps) r.only_keys(given, at, {"name", "params", "file"});
    else r.only_keys(given, at, {"name", "params", "label"});
    const bool file = given.contains("file");
    if (file) {
      r.path(given["file"], at + (item.is_string() ? "" : ".file"));  // a non-empty string
      e.head["file"] = given["file"];
      e.token = name_safe(fs::path(given["file"].get<std::string>()).stem().string());
    }
    if (given.contains("name") || !file) {
      if (!given.contains("name")) r.fail(at + ".name", "missing (give a \"name\"" + std::string(maps ? " or a \"file\")" : ")"));
      const std::string name = r.string(given["name"], at + ".name");
      e.head["name"] = name;
      if (!file) e.token = name_safe(name);
    }
    const std::string plugin = e.head.value("name", std::string("json"));
    const Parameters* schema = nullptr;
    try {
      schema = &lookup(plugin);
    } catch (const UnknownPlugin& error) {
      r.fail(given.contains("name") && !item.is_string() ? at + ".name" : at, error.what());
    }
    if (given.contains("params")) {
      const json& params = given["params"];
      const std::string pfield = at + ".params";
      if (!params.is_object()) r.fail(pfield, show(params) + " must be an object of parameter values");
      for (const auto& item_param : params.items()) {
        const std::string& key = item_param.key();
        if (std::none_of(schema->begin(), schema->end(), [&](const Parameter& p) { return p.name == key; })) {
          std::string declared;
          for (const auto& p : *schema) declared += (declared.empty() ? "" : ", ") + p.name;
          r.fail(Reader::join(pfield, key), "unknown parameter of " + std::string(maps ? "map '" : "behavior '") + plugin +
                                                "' (declared: " + (declared.empty() ? "none" : declared) + ")");
        }
      }
      for (const Parameter& p : *schema)
        if (params.contains(p.name))
          e.params.push_back({p.name, short_name(*schema, p.name), param_values(params[p.name], pfield + "." + p.name, p, r)});
    }
    if (given.contains("label")) {  // a behavior's short name for its variant: one variant's
      e.head["label"] = r.label(given["label"], at + ".label");
      for (const auto& p : e.params)
        if (p.values.size() > 1)
          r.fail(at + ".label", "names one variant, and " + at + ".params." + p.name + " gives " + std::to_string(p.values.size()) +
                                    " (allowed: a label on an entry whose parameters have one value each)");
    }
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace

Sweep read_sweep(const json& s, const Reader& r, const PluginHost& host, const Shared& shared) {
  r.only_keys(s, "sweep", {"test", "behaviors", "maps", "drones", "targets", "drone", "set"});
  Sweep sweep;
  json own = json::object();  // sweep.test as given; sweep.base is it laid over the queue's base
  if (s.contains("test")) {
    own = s["test"];
    if (!own.is_object()) r.fail("sweep.test", show(own) + " must be a test object (the fields every swept test shares)");
    if (shared.named() && own.contains("condition")) r.fail("sweep.test.condition", "set by the queue's conditions (allowed: leave it out)");
  }
  sweep.base = merged(shared.base, own, true);
  sweep.conditions = shared.conditions;
  const json& base = sweep.base;
  auto origin = [&](const std::string& key) { return (own.contains(key) ? "sweep.test." : "base.") + key; };
  // A key is given once: in sweep.test (or the base), or by the axis that sweeps it.
  auto once = [&](const char* axis, const char* key) {
    if (s.contains(axis) && base.contains(key)) r.fail(origin(key), std::string("also swept by sweep.") + axis + " (allowed: one or the other)");
  };
  once("behaviors", "behavior");
  once("maps", "map");
  once("drones", "drones");
  once("drone", "drone");
  // The behaviors, drones and drone axes set the single form's fields: with groups, each group has its own.
  if (base.contains("groups") && base["groups"].is_array())
    for (const auto& [axis, key, instead] : {std::tuple{"behaviors", "behavior", "groups.<name>.behavior.params.<p>"},
                                             {"drones", "drones", "groups.<name>.drones"}, {"drone", "drone", "groups.<name>.drone.<property>"}})
      if (s.contains(axis))
        r.fail(std::string("sweep.") + axis, std::string(own.contains("groups") ? "sweep.test" : "base") + " has \"groups\", each with its own " + key +
                                                 " (allowed beside groups: sweep.maps, sweep.targets, and sweep.set with keys such as " + instead +
                                                 ", <name> one of: " + entry_names(base["groups"]) + ")");
  if (s.contains("behaviors"))
    sweep.behaviors = plugin_axis(s["behaviors"], "sweep.behaviors", r, false,
                                  [&](const std::string& name) -> const Parameters& { return host.behavior(name).factory.parameters; });
  if (s.contains("maps"))
    sweep.maps = plugin_axis(s["maps"], "sweep.maps", r, true,
                             [&](const std::string& name) -> const Parameters& { return host.map(name).factory.parameters; });

  const std::string count_example = "[10, 20, 30] or {\"from\": 10, \"to\": 50, \"step\": 10}";
  if (s.contains("drones")) {
    const json& axis = s["drones"];
    std::vector<double> counts;
    std::unordered_set<double> seen;
    if (axis.is_object()) {
      for (const double x : range_values(axis, "sweep.drones", r)) {
        if (x != std::floor(x) || x < 1 || x > static_cast<double>(max_test_drones))
          r.fail("sweep.drones", show(axis) + " gives " + format::number(x) + ", which is out of range (allowed: whole number in [1, " +
                                     std::to_string(max_test_drones) + "])");
        counts.push_back(x);
      }
    } else {
      for (std::size_t i = 0; const json& item : list_axis(axis, "sweep.drones", r, count_example.c_str())) {
        const std::string at = "sweep.drones[" + std::to_string(i++) + "]";
        counts.push_back(static_cast<double>(r.integer(item, at, 1, max_test_drones)));
        if (!seen.insert(counts.back()).second) r.fail(at, show(item) + " is already in the list (allowed: each value once)");
      }
    }
    for (std::size_t i = 0; i < counts.size(); ++i)
      sweep.drones.push_back({{{"drones", counts[i]}}, "d" + number_token(counts[i]), "drones[" + std::to_string(i) + "]"});
  }

  if (s.contains("targets")) {
    // Counts (with sweep.test's kind and parameters), or whole targets objects.
    const json& axis = s["targets"];
    if (axis.is_object()) {
      if (base.contains("targets") && base["targets"].is_object() && base["targets"].contains("count"))
        r.fail(origin("targets") + ".count", "also swept by sweep.targets (allowed: one or the other)");
      for (const double x : range_values(axis, "sweep.targets", r)) {
        if (x != std::floor(x) || x < 0 || x > 10'000'000)
          r.fail("sweep.targets", show(axis) + " gives " + format::number(x) + ", which is out of range (allowed: whole number in [0, 10000000])");
        sweep.targets.push_back({{{"targets", {{"count", x}}}}, "t" + number_token(x), "targets[" + std::to_string(sweep.targets.size()) + "]"});
      }
    } else {
      for (std::size_t i = 0; const json& item : list_axis(axis, "sweep.targets", r, "[100, 500] or [{\"kind\": \"tree\", \"count\": 100, \"params\": {\"radius\": 3}}]")) {
        const std::string at = "sweep.targets[" + std::to_string(i) + "]";
        Point p{json::object(), "", "targets[" + std::to_string(i++) + "]"};
        if (item.is_object()) {
          if (base.contains("targets")) r.fail(origin("targets"), "also swept by " + at + " (allowed: one or the other; or sweep counts only)");
          r.only_keys(item, at, {"kind", "count", "params"});
          const std::uint64_t count = item.contains("count") ? r.integer(item["count"], at + ".count", 0, 10'000'000) : 0;
          const std::string kind = item.contains("kind") ? r.string(item["kind"], at + ".kind") : "tree";
          try {
            const auto& schema = host.target_kind(kind).factory.parameters;
            const ParameterValues values = r.params(item.value("params", json()), at + ".params", schema, "target kind '" + kind + "'");
            p.token = (item.contains("kind") ? name_safe(kind) : "t") + std::to_string(count);
            if (item.contains("params"))
              for (const Parameter& param : schema)
                if (item["params"].contains(param.name))
                  p.token += "_" + short_name(schema, param.name) + number_token(values.get(param.name));
          } catch (const UnknownPlugin& e) {
            r.fail(at + ".kind", e.what());
          }
          p.set["targets"] = item;
        } else {
          if (base.contains("targets") && base["targets"].is_object() && base["targets"].contains("count"))
            r.fail(origin("targets") + ".count", "also swept by sweep.targets (allowed: one or the other)");
          const std::uint64_t count = r.integer(item, at, 0, 10'000'000);
          p.set["targets"] = {{"count", count}};
          p.token = "t" + std::to_string(count);
        }
        sweep.targets.push_back(std::move(p));
      }
    }
  }

  if (s.contains("drone")) {
    // Named configurations (built in, or from sweep.test's drone_configs) or inline ones with a name.
    std::vector<DroneConfig> named = builtin_drone_configs();
    if (base.contains("drone_configs")) named = detail::drone_configs_file(r.path(base["drone_configs"], "sweep.test.drone_configs"));
    for (std::size_t i = 0; const json& item : list_axis(s["drone"], "sweep.drone", r, "[\"small\", \"medium\", {\"name\": \"fast\", \"base\": \"small\", \"max_speed\": 15}]")) {
      const std::string at = "sweep.drone[" + std::to_string(i) + "]";
      if (item.is_object() && !item.contains("name"))
        r.fail(at + ".name", "missing (a configuration in a sweep needs a \"name\": it goes into the test names)");
      const DroneConfig d = detail::parse_drone(item, r, named, at);
      sweep.drone.push_back({{{"drone", item}}, name_safe(d.name), "drone[" + std::to_string(i++) + "]"});
    }
  }
  if (s.contains("set")) sweep.set = set_axes(s["set"], s, base, own, r);

  // What the sweep sets is its own: a condition changes the base only.
  if (shared.named()) {
    std::vector<std::pair<std::string, std::string>> swept;  // (path, where)
    for (const auto& [axis, key] : {std::pair{"behaviors", "behavior"}, {"maps", "map"}, {"drones", "drones"}, {"drone", "drone"}})
      if (s.contains(axis)) swept.emplace_back(key, std::string("sweep.") + axis);
    for (const Point& p : sweep.targets)  // counts keep the base's kind and parameters
      swept.emplace_back(p.set["targets"].size() == 1 ? "targets.count" : "targets", "sweep.targets");
    for (const auto& axis : sweep.set) {
      const std::string key = axis.front().set.begin().key();
      swept.emplace_back(key, "sweep.set." + key);
    }
    std::vector<std::string> leaves;
    leaf_paths(own, "", leaves);
    for (const std::string& leaf : leaves) swept.emplace_back(leaf, "sweep.test." + leaf);
    for (const Condition& c : sweep.conditions) c.check_apart(swept, r);
  }
  return sweep;
}

}  // namespace salsa::detail
