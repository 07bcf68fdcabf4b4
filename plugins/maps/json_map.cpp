// Maps read from JSON files; the format is documented in docs/maps.md. This plugin reads the file's
// shape (a point is two numbers, a shape an array of points); the map rules (bounds, points within them,
// enough points, a free spawn point) are the core's, checked in one place for every map file
// (map_check.hpp). Every error is a MapError of one line naming the file, the field, the offending
// value and what is allowed.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <salsa/sdk.hpp>

#include "strict_json.hpp"  // the core's strict reading: depth, duplicate keys, numbers, UTF-8, file checks

namespace {

using nlohmann::json;

std::string shown(const json& j) { return salsa::strict_json::shown(j); }

class Reader {
 public:
  explicit Reader(const std::string& file) : file_(file) {}

  salsa::MapData read() const {
    const json root = parse();
    if (!root.is_object()) fail("", "the top level must be an object, got " + shown(root));
    for (const auto& [key, value] : root.items())
      if (key != "bounds" && key != "spawn" && key != "obstacles" && key != "hollow" && key != "lines")
        fail("", "unknown key '" + salsa::strict_json::printable(key) + "' (allowed: bounds, spawn, obstacles, hollow, lines)");

    salsa::MapData map;
    if (!root.contains("bounds")) fail("bounds", "missing; expected {\"min\": [x, y], \"max\": [x, y]}");
    const json& bounds = root["bounds"];
    if (!bounds.is_object())
      fail("bounds", "expected {\"min\": [x, y], \"max\": [x, y]}, got " + shown(bounds));
    for (const auto& [key, value] : bounds.items())
      if (key != "min" && key != "max") fail("bounds", "unknown key '" + salsa::strict_json::printable(key) + "' (allowed: min, max)");
    if (!bounds.contains("min") || !bounds.contains("max")) fail("bounds", "needs both \"min\" and \"max\"");
    map.bounds = {point(bounds["min"], "bounds.min"), point(bounds["max"], "bounds.max")};
    map.obstacles = polylines(root, "obstacles", "polygon", true);
    map.hollow = polylines(root, "hollow", "outline", true);
    map.lines = polylines(root, "lines", "line", false);
    map.spawn = root.contains("spawn") ? point(root["spawn"], "spawn") : map.bounds.centre();
    return map;
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw salsa::MapError(salsa::strict_json::printable(file_, 200) + ": " + (field.empty() ? "" : field + ": ") +
                          salsa::strict_json::printable(what, 1000));
  }

  json parse() const {
    try {
      return salsa::strict_json::read_file<json>(file_, "a map object, {\"bounds\": {\"min\": [x, y], \"max\": [x, y]}, ...}");
    } catch (const salsa::strict_json::Error& e) {
      throw salsa::MapError(e.what());
    }
  }

  salsa::Vec2 point(const json& j, const std::string& field) const {
    if (!j.is_array() || j.size() != 2 || !j[0].is_number() || !j[1].is_number())
      fail(field, "expected a point [x, y] of two numbers, got " + shown(j));
    return {j[0].get<double>(), j[1].get<double>()};  // finite: the reader refuses anything else
  }

  /// The shapes under `key`, as written; a closed shape (obstacles, hollow) may repeat its first point at
  /// the end, which is dropped (the closing edge is implied anyway).
  std::vector<salsa::Polyline> polylines(const json& root, const std::string& key, const std::string& what, bool closed) const {
    std::vector<salsa::Polyline> out;
    if (!root.contains(key)) return out;
    const json& list = root[key];
    if (!list.is_array()) fail(key, "expected an array of " + what + "s (arrays of [x, y]), got " + shown(list));
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string field = key + "[" + std::to_string(i) + "]";
      if (!list[i].is_array()) fail(field, "expected an array of points [x, y], got " + shown(list[i]));
      salsa::Polyline& pts = out.emplace_back();
      for (std::size_t j = 0; j < list[i].size(); ++j) pts.push_back(point(list[i][j], field + "[" + std::to_string(j) + "]"));
      if (closed && pts.size() > 1 && pts.front() == pts.back()) pts.pop_back();
    }
    return out;
  }

  std::string file_;
};

class JsonMap final : public salsa::MapGenerator {
 public:
  salsa::MapData generate(const std::string& file, salsa::Rng&) const override {
    if (file.empty()) throw salsa::MapError("json map: parameter 'file' is required");
    return Reader(file).read();
  }
};

}  // namespace

SALSA_MAP(JsonMap, "json", "Map read from a JSON file")
