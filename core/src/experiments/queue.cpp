#include "salsa/core/experiments/queue.hpp"

#include "salsa/core/files/format.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "salsa/core/files/names.hpp"
#include "experiments/test_reader.hpp"

namespace salsa {

using detail::json;
using detail::num;
using detail::Reader;
using detail::show;
namespace fs = std::filesystem;

// ---- Paired seeds

namespace {

std::uint64_t fnv1a64(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

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
      changed += (changed.empty() ? "" : " ") + p.name + "=" + num(choice.params.get(p.name));
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
    std::vector<std::pair<std::string, std::string>> changed;
    for (const Parameter& p : host.behavior(b.name).factory.parameters)
      if (b.params.has(p.name) && b.params.get(p.name) != p.value) changed.emplace_back(p.name, num(b.params.get(p.name)));
    return variant_label(b.name, changed);
  };
  if (t.groups.size() == 1) return one(t.groups[0].behavior);
  std::string out;  // "scouts=flocking (defaults) / base=random_walk: speed = 2"
  for (const GroupSpec& g : t.groups) out += (out.empty() ? "" : " / ") + g.name + "=" + one(g.behavior);
  return out;
}

// ---- Reading a queue

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
  if (to < from) r.fail(field + ".to", show(v["to"]) + " is below \"from\" " + num(from) + " (allowed: to ≥ from)");
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
      r.fail(field + ".count", "1 gives one value, but \"from\" " + num(from) + " and \"to\" " + num(to) +
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
    for (const double x : range_values(v, field, r)) add(x, field, show(v) + " gives " + num(x) + ", which");
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

/// Test names hold letters, digits, '_', '-' and '.'; anything else in user text becomes '_'.
std::string name_safe(std::string text) {
  for (char& c : text)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '_';
  return text;
}

/// A number in a test name: "2", "0.5", "1e-09", "1e20" (no '+').
std::string number_token(double v) {
  std::string s = num(v);
  std::erase(s, '+');
  return s;
}

/// How a parameter shows in test names: the initials of a name with '_' (cohesion_weight: "cw"), a
/// one-word name whole ("size"); the full name when two parameters of the plugin would look alike.
std::string short_name(const Parameters& schema, const std::string& name) {
  auto initials = [](const std::string& n) {
    if (n.find('_') == std::string::npos) return n;
    std::string out;
    for (std::size_t i = 0; i < n.size(); ++i)
      if (n[i] != '_' && (i == 0 || n[i - 1] == '_')) out += n[i];
    return out;
  };
  const std::string mine = initials(name);
  for (const Parameter& p : schema)
    if (p.name != name && initials(p.name) == mine) return name;
  return mine;
}

/// One value of a sweep axis: the keys it sets in the test, how it shows in names, where it was given.
struct Point {
  json set;          // {"drones": 30}, {"behavior": {...}}, ...
  std::string token;  // "d30", "flocking_cw2"
  std::string at;     // "drones[2]"
};

/// An entry of the behaviors or maps axis: a plugin with each parameter's values; it stands for the
/// product of those values.
struct SweptPlugin {
  std::string at;     // "behaviors[1]"
  json head;          // {"name": "forest"} or {"file": "maps/x.json"}
  std::string token;  // "forest", or the map file's stem
  struct Values {
    std::string name, short_name;
    std::vector<double> values;
  };
  std::vector<Values> params;  // in declaration order, so that names do not depend on the key order

  double size() const {
    double n = 1;
    for (const auto& p : params) n *= static_cast<double>(p.values.size());
    return n;
  }
  /// The product, last parameter fastest.
  std::vector<Point> points(const char* key) const {
    std::vector<Point> out;
    std::vector<std::size_t> index(params.size(), 0);
    for (;;) {
      Point p{{{key, head}}, token, at};
      if (!params.empty()) p.set[key]["params"] = json::object();
      for (std::size_t k = 0; k < params.size(); ++k) {
        const double v = params[k].values[index[k]];
        p.set[key]["params"][params[k].name] = v;
        p.token += "_" + params[k].short_name + number_token(v);
      }
      out.push_back(std::move(p));
      std::size_t k = params.size();
      while (k > 0 && ++index[k - 1] == params[k - 1].values.size()) index[--k] = 0;
      if (k == 0) return out;
    }
  }
};

// ---- sweep.set: any number of the test, by the dotted key timed changes use

const char* const set_key_forms =
    "a dotted path to a number of the test: drones, drone.<property>, behavior.params.<p>, groups.<name>.drones, "
    "groups.<name>.drone.<property>, groups.<name>.behavior.params.<p>, failures.drone_mtbf, failures.camera_mtbf, comm.<field>, "
    "wind.velocity.x, wind.gusts.strength, wind.field.params.<p>, ...";

/// A whole number as a JSON integer (messages and config.json show 20, not 20.0).
json as_json(double x) {
  if (x == std::floor(x) && std::fabs(x) < 9007199254740992.0) return static_cast<std::int64_t>(x);
  return x;
}

std::vector<std::string> key_parts(const std::string& key) {
  std::vector<std::string> out;
  for (std::size_t start = 0;;) {
    const std::size_t dot = key.find('.', start);
    out.push_back(key.substr(start, dot - start));
    if (dot == std::string::npos) return out;
    start = dot + 1;
  }
}

/// The name of a list entry: a string, or an object's "name"; "" for anything else.
std::string entry_name(const json& e) {
  if (e.is_string()) return e.get<std::string>();
  if (e.is_object() && e.contains("name") && e["name"].is_string()) return e["name"].get<std::string>();
  return "";
}

std::string entry_names(const json& list) {
  std::string out;
  for (const json& e : list) out += (out.empty() ? "" : ", ") + entry_name(e);
  return out.empty() ? "none" : out;
}

void check_key(const std::string& key, const std::string& field, const Reader& r) {
  for (const std::string& part : key_parts(key))
    if (part.empty() || !std::all_of(part.begin(), part.end(), [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; }))
      r.fail(field, "not a dotted key of letters, digits, '_' and '-' (allowed: " + std::string(set_key_forms) + ")");
}

/// Where `key` points in `test`, made to exist: a missing object is added, a list is entered by an
/// entry's name (groups.scouts: the group named "scouts"), and a choice given by name becomes the object
/// that can hold the number ("large" → {"base": "large"} for a drone, "flocking" → {"name": "flocking"},
/// a map file → {"file": ...}). Fails, naming `field` (sweep.set.<key>), where the path cannot go on;
/// `owner` names `test` in messages (sweep.test).
json& place(json& test, const std::string& key, const Reader& r, const std::string& field, const std::string& owner_name) {
  const std::vector<std::string> parts = key_parts(key);
  json* at = &test;
  std::string walked;  // "groups.scouts", for messages
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    if (at->is_string()) {
      const std::string name = at->get<std::string>();
      const std::string& owner = parts[i - 1];
      *at = owner == "drone" ? json{{"base", name}} : owner == "map" && name.ends_with(".json") ? json{{"file", name}} : json{{"name", name}};
    }
    if (i == 1 && parts[0] == "groups" && !at->is_array())
      r.fail(field, owner_name + " has no \"groups\" (allowed: groups.<name>.<key> with the groups given in " + owner_name + ")");
    if (at->is_null()) *at = json::object();
    if (at->is_array()) {
      const auto it = std::find_if(at->begin(), at->end(), [&](const json& e) { return entry_name(e) == part; });
      if (it == at->end()) r.fail(field, "no '" + part + "' in " + owner_name + "." + walked + " (allowed: " + entry_names(*at) + ")");
      at = &*it;
    } else if (at->is_object()) {
      at = &(*at)[part];
    } else {
      r.fail(field, owner_name + "." + walked + " is " + show(*at) + ", which holds no " + part + " (allowed: " + set_key_forms + ")");
    }
    walked += (walked.empty() ? "" : ".") + part;
  }
  return *at;
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

// ---- The base and the conditions

/// `over` laid on `base`: objects merge key by key, recursively; anything else replaces the base's value,
/// and so does an object naming another plugin or drone configuration (its "name", "kind", "file" or
/// "base" differ). `top`: test objects, whose "name" is the test's.
json merged(const json& base, const json& over, bool top = false) {
  if (!base.is_object() || !over.is_object()) return over;
  if (!top) {
    auto id = [](const json& o) {
      json out = json::object();
      for (const char* key : {"name", "kind", "file", "base"})
        if (o.contains(key)) out[key] = o[key];
      return out;
    };
    if (const json mine = id(over); !mine.empty() && mine != id(base)) return over;
  }
  json out = base;
  for (const auto& [key, value] : over.items()) out[key] = out.contains(key) ? merged(out[key], value) : value;
  return out;
}

/// The dotted paths of what a test object sets: its leaves (an object's keys, recursively; a list or
/// an empty object is a leaf).
void leaf_paths(const json& v, const std::string& at, std::vector<std::string>& out) {
  if (v.is_object() && !v.empty()) {
    for (const auto& [key, value] : v.items()) leaf_paths(value, at.empty() ? key : at + "." + key, out);
    return;
  }
  if (!at.empty()) out.push_back(at);
}

/// Whether two dotted paths set the same thing: equal, or one inside the other.
bool overlaps(const std::string& a, const std::string& b) { return a == b || a.starts_with(b + ".") || b.starts_with(a + "."); }

/// A JSON value in words: numbers as config.json writes them, strings bare.
std::string words(const json& v) {
  if (v.is_number()) return num(v.get<double>());
  if (v.is_string()) return v.get<std::string>();
  return show(v);
}

/// One entry of "conditions": test fields laid over the base, and dotted keys set as sweep.set's are.
/// The queue's tests are each run under every condition; a queue without conditions has one unnamed.
struct Condition {
  std::string name, label;       // label: what it changes from the base, in words
  std::string at;                // "conditions[1]"
  json fields = json::object();  // test keys
  json set = json::object();     // dotted key -> value
  std::vector<std::string> paths;  // what it sets: the leaves of `fields` and the keys of `set`

  /// `test` with the condition laid over it (its fields, then its keys) and its labels; `owner` names
  /// the test in messages.
  void apply(json& test, const Reader& r, const std::string& owner) const {
    if (name.empty() || !test.is_object()) return;  // not a test object: the test reader says so
    test = merged(test, fields, true);
    for (const auto& [key, value] : set.items()) place(test, key, r, Reader::join(at + ".set", key), owner) = value;
    test["condition"] = {{"name", name}, {"label", label}};
  }
  /// Refuses a condition that sets what a test or the sweep sets itself: (path, where it is set), e.g.
  /// ("drones", "sweep.drones"), ("changes", "tests[0].changes").
  void check_apart(const std::vector<std::pair<std::string, std::string>>& theirs, const Reader& r) const {
    for (const std::string& mine : paths)
      for (const auto& [other, by] : theirs)
        if (overlaps(mine, other))
          r.fail(at + "." + mine, "also set by " + by + " (allowed: one or the other; a condition changes the base, not what a test or the sweep sets)");
  }
};

/// "drones → 14 at 200 s, wind.velocity.x = 3": what a condition changes, in words; "no change" when nothing.
std::string condition_label(const json& fields, const json& set) {
  std::string out;
  auto add = [&](const std::string& part) { out += (out.empty() ? "" : ", ") + part; };
  std::vector<std::string> leaves;
  leaf_paths(fields, "", leaves);
  for (const std::string& path : leaves) {
    if (path == "changes" && fields["changes"].is_array()) {
      for (const json& change : fields["changes"])
        if (change.is_object() && change.contains("set") && change["set"].is_object())
          for (const auto& [key, value] : change["set"].items())
            add(key + " → " + words(value) + (change.contains("time") ? " at " + words(change["time"]) + " s" : ""));
      continue;
    }
    const json* v = &fields;
    for (const std::string& part : key_parts(path)) v = &(*v)[part];
    add(path + " = " + words(*v));
  }
  for (const auto& [key, value] : set.items()) add(key + " = " + words(value));
  return out.empty() ? "no change" : out;
}

std::vector<Condition> read_conditions(const json& list, const Reader& r) {
  if (!list.is_array() || list.empty())
    r.fail("conditions", show(list) + " must be a non-empty list of conditions, e.g. [{\"name\": \"baseline\"}, "
                                      "{\"name\": \"dropout\", \"changes\": [{\"time\": 200, \"set\": {\"drones\": 14}}]}]");
  std::vector<const char*> allowed{"name", "set"};
  for (const char* key : detail::test_keys)  // the test's own: its name, seed, repeat and provenance are not a condition's
    if (std::string_view(key) != "name" && std::string_view(key) != "seed" && std::string_view(key) != "repeat" &&
        std::string_view(key) != "condition" && std::string_view(key) != "versions")
      allowed.push_back(key);
  std::vector<Condition> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    Condition c;
    c.at = "conditions[" + std::to_string(i) + "]";
    const json& entry = list[i];
    r.only_keys(entry, c.at, allowed);
    if (!entry.contains("name")) r.fail(c.at + ".name", "missing (a condition's name goes into its tests' names and the plots)");
    c.name = r.string(entry["name"], c.at + ".name");
    if (name_safe(c.name) != c.name)
      r.fail(c.at + ".name", show(entry["name"]) + " has characters a test name cannot hold (allowed: letters, digits, '_', '-' and '.')");
    for (const Condition& earlier : out)
      if (earlier.name == c.name) r.fail(c.at + ".name", show(entry["name"]) + " is already the name of " + earlier.at + " (allowed: each name once)");
    for (const auto& [key, value] : entry.items())
      if (key != "name" && key != "set") c.fields[key] = value;
    if (entry.contains("set")) {
      c.set = entry["set"];
      if (!c.set.is_object() || c.set.empty())
        r.fail(c.at + ".set", show(c.set) + " must be an object of dotted keys and their values, e.g. {\"groups.scouts.drones\": 4}");
      for (const auto& [key, value] : c.set.items()) {
        check_key(key, Reader::join(c.at + ".set", key), r);
        c.paths.push_back(key);
      }
    }
    leaf_paths(c.fields, "", c.paths);
    for (std::size_t a = 0; a < c.paths.size(); ++a)  // a key set twice: in the fields and in "set"
      for (std::size_t b = a + 1; b < c.paths.size(); ++b)
        if (overlaps(c.paths[a], c.paths[b])) r.fail(c.at + "." + c.paths[b], "also set by " + c.at + "." + c.paths[a] + " (allowed: once)");
    c.label = condition_label(c.fields, c.set);
    out.push_back(std::move(c));
  }
  return out;
}

/// The queue's base and conditions; without "conditions", one unnamed condition that changes nothing.
struct Shared {
  json base = json::object();
  std::vector<Condition> conditions{Condition{}};
  bool named() const { return !conditions.front().name.empty(); }
};

Shared read_shared(const json& j, const Reader& r) {
  Shared out;
  if (j.contains("base")) {
    out.base = j["base"];
    if (!out.base.is_object()) r.fail("base", show(out.base) + " must be a test object (the fields every test of the queue shares)");
    if (out.base.contains("name")) r.fail("base.name", "a test's name is its own (allowed: a name in each test, or sweep.test's for the sweep's)");
  }
  if (j.contains("conditions")) {
    out.conditions = read_conditions(j["conditions"], r);
    if (out.base.contains("condition")) r.fail("base.condition", "set by the queue's conditions (allowed: leave it out)");
  }
  return out;
}

/// The sweep of a queue file, read and checked, not yet multiplied out.
struct Sweep {
  json base = json::object();  // sweep.test
  std::vector<SweptPlugin> behaviors, maps;
  std::vector<Point> drones, targets, drone;
  std::vector<std::vector<Point>> set;  // one axis per key of sweep.set, in key order; each point sets {key: value}
  std::vector<Condition> conditions;     // the queue's, each laid over every swept test

  /// Tests per repeat (a double: the product can be far too large, and is refused then).
  double size() const {
    auto sum = [](const std::vector<SweptPlugin>& entries) {
      double n = 0;
      for (const auto& e : entries) n += e.size();
      return entries.empty() ? 1.0 : n;
    };
    auto count = [](const std::vector<Point>& points) { return points.empty() ? 1.0 : static_cast<double>(points.size()); };
    double n = sum(behaviors) * sum(maps) * count(drones) * count(targets) * count(drone);
    for (const auto& axis : set) n *= count(axis);
    return n * static_cast<double>(conditions.size());
  }
};

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
    else r.only_keys(given, at, {"name", "params"});
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
    out.push_back(std::move(e));
  }
  return out;
}

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
        if (x != std::floor(x) || x < 1 || x > 1'000'000)
          r.fail("sweep.drones", show(axis) + " gives " + num(x) + ", which is out of range (allowed: whole number in [1, 1000000])");
        counts.push_back(x);
      }
    } else {
      for (std::size_t i = 0; const json& item : list_axis(axis, "sweep.drones", r, count_example.c_str())) {
        const std::string at = "sweep.drones[" + std::to_string(i++) + "]";
        counts.push_back(static_cast<double>(r.integer(item, at, 1, 1'000'000)));
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
          r.fail("sweep.targets", show(axis) + " gives " + num(x) + ", which is out of range (allowed: whole number in [0, 10000000])");
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

/// A name fit for a folder: past 128 characters, the start, a hash of the whole and the repeat suffix.
std::string fitted(const std::string& name, const std::string& suffix) {
  if (name.size() + suffix.size() <= max_name_length) return name + suffix;
  char hash[12];
  std::snprintf(hash, sizeof hash, "_%08x", static_cast<unsigned>(fnv1a64(name) >> 32));
  return name.substr(0, max_name_length - suffix.size() - 9) + hash + suffix;
}

/// A test without "name" is named after its file; that name must be fit for a folder too.
void name_after_file(TestSpec& t, const std::string& name) {
  if (!t.name.empty()) return;
  if (const std::string why = test_name_problem(name); !why.empty())
    throw InputError(t.source + ": name: missing, and the file name cannot stand in for it: " + why + "; give the test a \"name\"");
  t.name = name;
}

/// A configuration: one test before it is repeated.
struct Config {
  TestSpec test;
  std::string where;  // for messages about the seed and the repeat keys
  std::string name;   // without the repeat suffix; empty: keep test.name
  std::string at;     // a sweep's test: the axis values it was made of ("behaviors[1], drones[0]")
};

/// One test of a sweep before it is read: sweep.test with one value of each axis set.
struct Swept {
  json test;
  std::string name;  // without the repeat suffix, not yet fitted
  std::string at;    // the axis values it was made of: "behaviors[1], set.drones[0]"
};

/// Appends `part` to a name or a list, after `separator` unless either is empty.
void join(std::string& to, const std::string& part, const char* separator) {
  if (!part.empty()) to += (to.empty() ? "" : separator) + part;
}

/// How a test object's behavior shows in its name: "flocking"; with groups, theirs joined by '+' ("flocking+random_walk",
/// which name_safe makes "flocking_random_walk").
std::string behavior_name(const json& test) {
  if (test.contains("behavior")) return entry_name(test["behavior"]);
  std::string out;
  if (test.contains("groups") && test["groups"].is_array())
    for (const json& group : test["groups"])
      if (group.is_object() && group.contains("behavior")) out += (out.empty() ? "" : "+") + entry_name(group["behavior"]);
  return out;
}

/// Visits the sweep's tests in the order they run within a repeat, one at a time (a million test objects
/// at once would take gigabytes): maps outer, then drone configurations, drone counts, targets,
/// sweep.set's keys (the last faster), conditions, and behaviors fastest, so that the tests of one world
/// are neighbours.
template <class Visit>
void multiply(const Sweep& sweep, const Reader& r, Visit visit) {
  auto points = [](const std::vector<SweptPlugin>& entries, const char* key) {
    std::vector<Point> out;
    for (const auto& e : entries)
      for (auto& p : e.points(key)) out.push_back(std::move(p));
    return out;
  };
  const std::vector<Point> none{Point{json::object(), "", ""}};
  const std::vector<Point> behaviors = sweep.behaviors.empty() ? none : points(sweep.behaviors, "behavior");
  const std::vector<Point> maps = sweep.maps.empty() ? none : points(sweep.maps, "map");
  const std::vector<Point>& drone = sweep.drone.empty() ? none : sweep.drone;
  const std::vector<Point>& drones = sweep.drones.empty() ? none : sweep.drones;
  const std::vector<Point>& targets = sweep.targets.empty() ? none : sweep.targets;
  std::vector<Point> sets = none;  // sweep.set's axes as one: their product
  for (const std::vector<Point>& axis : sweep.set) {
    std::vector<Point> product;
    product.reserve(sets.size() * axis.size());
    for (const Point& outer : sets)
      for (const Point& p : axis) {
        Point both = outer;
        both.set.update(p.set);
        join(both.token, p.token, "_");
        join(both.at, p.at, ", ");
        product.push_back(std::move(both));
      }
    sets = std::move(product);
  }
  const std::string prefix = sweep.base.contains("name") && sweep.base["name"].is_string() ? sweep.base["name"].get<std::string>() : "";
  for (const Point& m : maps)
    for (const Point& dc : drone)
      for (const Point& n : drones)
        for (const Point& tg : targets)
          for (const Point& st : sets)
            for (const Condition& c : sweep.conditions)
            for (const Point& b : behaviors) {
              Swept t{sweep.base, prefix, ""};
              for (const Point* p : {&b, &n, &tg, &m, &dc}) {
                for (const auto& [key, value] : p->set.items()) {
                  if (key == "targets" && value.size() == 1 && value.contains("count") && t.test.contains("targets") && t.test["targets"].is_object())
                    t.test["targets"]["count"] = value["count"];  // a count: kind and parameters from sweep.test
                  else
                    t.test[key] = value;
                }
              }
              for (const auto& [key, value] : st.set.items()) place(t.test, key, r, Reader::join("sweep.set", key), "sweep.test") = value;
              c.apply(t.test, r, "sweep.test");
              join(t.name, b.token.empty() ? behavior_name(t.test) : b.token, "_");
              for (const Point* p : {&n, &tg, &m, &dc, &st}) join(t.name, p->token, "_");
              join(t.name, c.name, "_");
              for (const Point* p : {&b, &n, &tg, &m, &dc, &st}) join(t.at, p->at, ", ");
              join(t.at, c.at, ", ");
              visit(std::move(t));
            }
}

}  // namespace

Queue load_queue(const fs::path& file, const PluginHost& host, const QueueOptions& options) {
  const json j = detail::read_json_file(file, "a test, a list of tests, or a queue {\"tests\": [...], \"sweep\": {...}}");
  const std::string shown_file = strict_json::printable(file.string(), 200);
  const Reader r(shown_file, file.parent_path());
  const std::string stem = file.stem().string();
  Queue queue;
  queue.source = shown_file;

  // ---- The file's shape: a queue object, a list of tests, or one test.
  const bool is_queue = j.is_object() && (j.contains("tests") || j.contains("sweep") || j.contains("repeats") || j.contains("conditions"));
  const json* tests = nullptr;
  std::string list_field;  // "tests", or "" for a top-level list
  std::size_t repeats = 1;
  if (is_queue) {
    r.only_keys(j, "", {"seed", "repeats", "base", "conditions", "reference", "top", "tests", "sweep"});
    if (!j.contains("tests") && !j.contains("sweep"))
      r.fail("tests", "missing (a queue holds \"tests\", a \"sweep\", or both)");
    if (j.contains("seed")) queue.seed = r.integer(j["seed"], "seed", 0, 9007199254740992.0);
    if (j.contains("repeats")) repeats = r.integer(j["repeats"], "repeats", 1, static_cast<double>(max_queue_tests));
    if (j.contains("tests")) {
      tests = &j["tests"];
      list_field = "tests";
      if (!tests->is_array()) r.fail("tests", show(*tests) + " must be a list of tests");
    }
  } else if (j.is_array()) {
    tests = &j;
  }
  const Shared shared = is_queue ? read_shared(j, r) : Shared{};
  if (options.seed) queue.seed = *options.seed;
  if (tests && tests->empty()) throw InputError(shown_file + ": " + (list_field.empty() ? "the list" : list_field) + " holds no tests");

  // ---- The explicit tests, then the sweep's axes (checked before anything is multiplied out).
  std::vector<Config> configs;
  if (!is_queue && !tests) {
    Config c{detail::parse_test(j, r, host), shown_file, "", ""};
    c.test.source = shown_file;
    name_after_file(c.test, stem);
    configs.push_back(std::move(c));
  }
  if (tests)
    for (std::size_t i = 0; i < tests->size(); ++i) {
      // The test laid over the base, under each condition (conditions vary faster).
      const std::string at = list_field + "[" + std::to_string(i) + "]";
      const json& own = (*tests)[i];
      std::vector<std::string> leaves;
      leaf_paths(own, "", leaves);
      std::vector<std::pair<std::string, std::string>> own_paths;  // what the test sets itself
      for (const std::string& leaf : leaves) own_paths.emplace_back(leaf, at + "." + leaf);
      if (shared.named() && own.is_object() && own.contains("condition"))
        r.fail(at + ".condition", "set by the queue's conditions (allowed: leave it out)");
      for (const Condition& condition : shared.conditions) {
        const std::string where = shown_file + ": " + at + (condition.name.empty() ? "" : " (" + condition.at + ")");
        const Reader reader(where, file.parent_path());
        json test = j.contains("base") ? merged(shared.base, own, true) : own;
        if (!condition.name.empty()) {
          condition.check_apart(own_paths, r);
          condition.apply(test, reader, at);
        }
        Config c{detail::parse_test(test, reader, host), where, "", ""};
        c.test.source = where;
        name_after_file(c.test, stem + "-" + std::to_string(i + 1));
        if (!condition.name.empty()) c.test.name = fitted(c.test.name + "_" + condition.name, "");
        configs.push_back(std::move(c));
      }
    }
  std::optional<Sweep> sweep;
  if (is_queue && j.contains("sweep")) sweep = read_sweep(j["sweep"], r, host, shared);

  const double per_repeat = static_cast<double>(configs.size()) + (sweep ? sweep->size() : 0);
  const double total = per_repeat * static_cast<double>(repeats);
  const std::string count = "the queue expands to " + grouped(total) + " tests (" +
                            (repeats > 1 ? grouped(per_repeat) + " × " + grouped(static_cast<double>(repeats)) + " repeats; " : "");
  if (total > static_cast<double>(max_queue_tests))
    throw InputError(shown_file + ": " + count + "allowed: at most " + grouped(max_queue_tests) +
                     " in one queue, even with --yes): split it into several files");
  if (total > static_cast<double>(options.max_tests) && !options.yes)
    throw InputError(shown_file + ": " + count + "allowed: " + grouped(static_cast<double>(options.max_tests)) +
                     " without --yes): check the sweep, or pass --yes to run them all");

  // ---- The sweep multiplied out, each test read: with sweep.set, a test's messages name the values it was made of.
  if (sweep) {
    const std::string base_where = shown_file + ": sweep.test";
    const Reader base_reader(base_where, file.parent_path());
    multiply(*sweep, r, [&](Swept&& s) {
      const Reader reader = s.at.empty() || (sweep->set.empty() && !shared.named()) ? base_reader
                                                                                 : Reader(shown_file + ": sweep (" + s.at + ")", file.parent_path());
      Config c{detail::parse_test(s.test, reader, host), base_where, std::move(s.name), s.at};
      c.test.source = shown_file + ": sweep" + (s.at.empty() ? "" : " (" + s.at + ")");
      configs.push_back(std::move(c));
    });
  }

  // ---- The comparison's pairs: each variant against a reference (a variant of the queue, or a
  // behavior's name for its defaults), or every pair of the `top` best. Not both: each is a whole
  // choice of pairs, and which variants rank best is known only after the run.
  std::vector<std::string> labels;
  if (is_queue && (j.contains("reference") || j.contains("top")))
    for (const Config& c : configs)
      if (std::string v = variant(c.test, host); std::find(labels.begin(), labels.end(), v) == labels.end()) labels.push_back(std::move(v));
  if (is_queue && j.contains("top")) {
    if (j.contains("reference"))
      r.fail("top", show(j["top"]) + " given with \"reference\" (allowed: one of them; \"top\" compares the best variants with each other, "
                                     "\"reference\" every variant with one)");
    if (labels.size() < 2) r.fail("top", show(j["top"]) + ": the queue has one variant, nothing to compare (allowed: leave it out)");
    queue.top = r.integer(j["top"], "top", 2, static_cast<double>(labels.size()));
  }
  if (is_queue && j.contains("reference")) {
    const std::string given = r.string(j["reference"], "reference");
    for (const std::string& wanted : {given, variant_label(given, {})})
      if (queue.reference.empty() && std::find(labels.begin(), labels.end(), wanted) != labels.end()) queue.reference = wanted;
    if (queue.reference.empty()) {
      std::string allowed;
      for (std::size_t i = 0; i < labels.size() && i < 20; ++i) allowed += (i ? "; " : "") + labels[i];
      r.fail("reference", show(j["reference"]) + " names no variant of the queue (allowed: " + allowed +
                              (labels.size() > 20 ? "; ..." : "") + "; or a behavior's name for its defaults)");
    }
  }

  // ---- Seeds: the paired seed unless the test gives its own (--seed overrides those too).
  std::vector<std::string> keys;
  keys.reserve(configs.size());
  for (const Config& c : configs) keys.push_back(world_key(c.test));
  auto seed_of = [&](const TestSpec& t, std::size_t i) {
    if (options.seed) return paired_seed(*options.seed, t.repeat, keys[i]);
    return t.seed_given ? t.seed : paired_seed(queue.seed, t.repeat, keys[i]);
  };
  for (std::size_t i = 0; i < configs.size(); ++i) {
    TestSpec& t = configs[i].test;
    t.seed = seed_of(t, i);
    if (repeats > 1 && t.repeat != 0)
      throw InputError(configs[i].where + ": repeat: " + std::to_string(t.repeat) + " is given, and the queue has \"repeats\": " +
                       std::to_string(repeats) + " (allowed: one or the other)");
    if (repeats > 1 && t.seed_given && !options.seed)
      throw InputError(configs[i].where + ": seed: " + std::to_string(t.seed) + " would be the seed of every repeat (\"repeats\": " +
                       std::to_string(repeats) + "), all the same test (allowed: no seed, for paired seeds; or --seed)");
  }

  // ---- The same test twice is a mistake: same world, same seed, same data.
  {
    std::vector<const TestSpec*> specs;
    specs.reserve(configs.size());
    for (const Config& c : configs) specs.push_back(&c.test);
    if (const auto same = first_same_test(specs))
      throw InputError(configs[same->second].test.source + ": the same test as " + configs[same->first].test.source +
                       " (the same world, seed and behavior give the same data; give one a \"seed\", or use the queue's \"repeats\")");
  }

  // ---- Repeats, interleaved: repeat 0 of every configuration before repeat 1 of any.
  queue.tests.reserve(configs.size() * repeats);
  for (std::size_t k = 0; k < repeats; ++k)
    for (std::size_t i = 0; i < configs.size(); ++i) {
      TestSpec t = configs[i].test;
      if (repeats > 1) {
        t.repeat = k;
        t.seed = seed_of(t, i);
        const std::string& at = configs[i].at;
        t.source = configs[i].at.empty() ? t.source + " (repeat " + std::to_string(k) + ")"
                                         : shown_file + ": sweep (" + at + ", repeat " + std::to_string(k) + ")";
      }
      const std::string suffix = "_r" + std::to_string(t.repeat);
      if (!configs[i].name.empty()) t.name = fitted(name_safe(configs[i].name), suffix);
      else if (repeats > 1) t.name = fitted(t.name, suffix);
      queue.tests.push_back(std::move(t));
    }

  std::unordered_map<std::string, std::size_t> names;
  for (std::size_t i = 0; i < queue.tests.size(); ++i) {
    const TestSpec& t = queue.tests[i];
    if (const auto [it, fresh] = names.emplace(t.name, i); !fresh)
      throw InputError(t.source + ": name: \"" + t.name + "\" is already used by " + queue.tests[it->second].source +
                       " (each test writes to a folder of its name)");
  }
  return queue;
}

std::vector<SweptTest> expand_sweep(const fs::path& file, const PluginHost& host) {
  const json j = detail::read_json_file(file, "a queue {\"sweep\": {...}}");
  const Reader r(strict_json::printable(file.string(), 200), file.parent_path());
  if (!j.is_object() || !j.contains("sweep")) r.fail("sweep", "missing (a queue with a \"sweep\")");
  const Sweep sweep = read_sweep(j["sweep"], r, host, read_shared(j, r));
  if (sweep.size() > static_cast<double>(max_queue_tests))
    r.fail("sweep", "expands to " + grouped(sweep.size()) + " tests (allowed: at most " + grouped(max_queue_tests) + ")");
  std::vector<SweptTest> out;
  multiply(sweep, r, [&](Swept&& s) { out.push_back({s.test.dump(), name_safe(s.name), s.at}); });
  return out;
}

std::string set_numbers(const std::string& test_json, const std::vector<std::pair<std::string, double>>& values,
                        const std::string& where) {
  json test = json::parse(test_json);
  const Reader r(where, {});
  for (const auto& [key, value] : values) place(test, key, r, Reader::join("parameters", key), "test") = as_json(value);
  return test.dump();
}

std::vector<TestSpec> load_tests(const fs::path& file, const PluginHost& host) { return load_queue(file, host, {}).tests; }

}  // namespace salsa
