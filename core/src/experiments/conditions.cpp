// A queue's "base" and "conditions": test objects laid over each other, what each condition sets and says.
#include <string_view>

#include "experiments/queue_reader.hpp"
#include "format.hpp"

namespace salsa::detail {

json merged(const json& base, const json& over, bool top) {
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

void leaf_paths(const json& v, const std::string& at, std::vector<std::string>& out) {
  if (v.is_object() && !v.empty()) {
    for (const auto& [key, value] : v.items()) leaf_paths(value, at.empty() ? key : at + "." + key, out);
    return;
  }
  if (!at.empty()) out.push_back(at);
}

bool overlaps(const std::string& a, const std::string& b) { return a == b || a.starts_with(b + ".") || b.starts_with(a + "."); }

namespace {

/// A JSON value in words: numbers as config.json writes them, strings bare.
std::string words(const json& v) {
  if (v.is_number()) return format::number(v.get<double>());
  if (v.is_string()) return v.get<std::string>();
  return show(v);
}

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
  // the test's own: its name, seed, repeat, provenance and outputs are not a condition's
  for (const char* key : detail::test_keys())
    if (std::string_view(key) != "name" && std::string_view(key) != "seed" && std::string_view(key) != "repeat" &&
        std::string_view(key) != "condition" && std::string_view(key) != "versions" && std::string_view(key) != "archive")
      allowed.push_back(key);
  allowed.push_back("label");
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
      if (key != "name" && key != "label" && key != "set") c.fields[key] = value;
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
    // The file's short label, or what the condition changes in words.
    c.label = entry.contains("label") ? r.label(entry["label"], c.at + ".label") : condition_label(c.fields, c.set);
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace

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

}  // namespace salsa::detail
