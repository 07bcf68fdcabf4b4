// Dotted keys into a test object ("groups.scouts.drones"): checked, followed and set (sweep.set, conditions, tune).
#include "salsa/core/experiments/queue.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "experiments/queue_reader.hpp"

namespace salsa {

namespace detail {

const char* const set_key_forms =
    "a dotted path to a number of the test: drones, drone.<property>, behavior.params.<p>, groups.<name>.drones, "
    "groups.<name>.drone.<property>, groups.<name>.behavior.params.<p>, failures.drone_mtbf, failures.camera_mtbf, comm.<field>, "
    "wind.velocity.x, wind.gusts.strength, wind.field.params.<p>, ...";

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

}  // namespace detail

using detail::as_json;
using detail::json;
using detail::place;
using detail::Reader;

std::string set_numbers(const std::string& test_json, const std::vector<std::pair<std::string, double>>& values,
                        const std::string& where) {
  json test = json::parse(test_json);
  const Reader r(where, {});
  for (const auto& [key, value] : values) place(test, key, r, Reader::join("parameters", key), "test") = as_json(value);
  return test.dump();
}

}  // namespace salsa
