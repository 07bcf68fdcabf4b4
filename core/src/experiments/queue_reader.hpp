#pragma once
// What the pieces that read a queue file share (queue, sweep, conditions, dotted_keys, queue_names). Internal to libsalsa.
#include <string>
#include <utility>
#include <vector>

#include "experiments/test_reader.hpp"

namespace salsa::detail {

// ---- Test names (queue_names.cpp)

/// Test names hold letters, digits, '_', '-' and '.'; anything else in user text becomes '_'.
std::string name_safe(std::string text);
/// A number in a test name: "2", "0.5", "1e-09", "1e20" (no '+').
std::string number_token(double v);
/// How a parameter shows in test names: the initials of a name with '_' (cohesion_weight: "cw"), a
/// one-word name whole ("size"); the full name when two parameters of the plugin would look alike.
std::string short_name(const Parameters& schema, const std::string& name);
/// A name fit for a folder: past 128 characters, the start, a hash of the whole and the repeat suffix.
std::string fitted(const std::string& name, const std::string& suffix);
/// A test without "name" is named after its file; that name must be fit for a folder too.
void name_after_file(TestSpec& t, const std::string& name);
/// Appends `part` to a name or a list, after `separator` unless either is empty.
void join(std::string& to, const std::string& part, const char* separator);
/// How a test object's behavior shows in its name: "flocking"; with groups, theirs joined by '+' ("flocking+random_walk",
/// which name_safe makes "flocking_random_walk").
std::string behavior_name(const json& test);

// ---- Dotted keys: any number of the test, by the dotted key timed changes use (dotted_keys.cpp)

/// What a dotted key may be, for messages.
extern const char* const set_key_forms;
/// A whole number as a JSON integer (messages and config.json show 20, not 20.0).
json as_json(double x);
std::vector<std::string> key_parts(const std::string& key);
/// The name of a list entry: a string, or an object's "name"; "" for anything else.
std::string entry_name(const json& e);
std::string entry_names(const json& list);
void check_key(const std::string& key, const std::string& field, const Reader& r);
/// Where `key` points in `test`, made to exist: a missing object is added, a list is entered by an
/// entry's name (groups.scouts: the group named "scouts"), and a choice given by name becomes the object
/// that can hold the number ("large" → {"base": "large"} for a drone, "flocking" → {"name": "flocking"},
/// a map file → {"file": ...}). Fails, naming `field` (sweep.set.<key>), where the path cannot go on;
/// `owner` names `test` in messages (sweep.test).
json& place(json& test, const std::string& key, const Reader& r, const std::string& field, const std::string& owner_name);

// ---- The base and the conditions (conditions.cpp)

/// `over` laid on `base`: objects merge key by key, recursively; anything else replaces the base's value,
/// and so does an object naming another plugin or drone configuration (its "name", "kind", "file" or
/// "base" differ). `top`: test objects, whose "name" is the test's.
json merged(const json& base, const json& over, bool top = false);
/// The dotted paths of what a test object sets: its leaves (an object's keys, recursively; a list or
/// an empty object is a leaf).
void leaf_paths(const json& v, const std::string& at, std::vector<std::string>& out);
/// Whether two dotted paths set the same thing: equal, or one inside the other.
bool overlaps(const std::string& a, const std::string& b);

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

/// The queue's base and conditions; without "conditions", one unnamed condition that changes nothing.
struct Shared {
  json base = json::object();
  std::vector<Condition> conditions{Condition{}};
  bool named() const { return !conditions.front().name.empty(); }
};

/// The queue's "base" and "conditions", checked.
Shared read_shared(const json& j, const Reader& r);

// ---- The sweep (sweep.cpp; queue.cpp multiplies it out)

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

/// The sweep of a queue file ("sweep"), read and checked against the queue's base and conditions.
Sweep read_sweep(const json& s, const Reader& r, const PluginHost& host, const Shared& shared);

}  // namespace salsa::detail
