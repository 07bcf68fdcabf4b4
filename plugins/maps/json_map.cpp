// Maps read from JSON files; the format is documented in docs/maps.md. Every error is a MapError of
// one line naming the file, the field, the offending value and what is allowed.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <salsa/sdk.hpp>

#include "format.hpp"       // how salsa writes points in messages
#include "strict_json.hpp"  // the core's strict reading: depth, duplicate keys, numbers, UTF-8, file checks

namespace {

using nlohmann::json;

std::string shown(const json& j) { return salsa::strict_json::shown(j); }

bool inside_polygon(salsa::Vec2 p, const salsa::Polyline& poly) {  // even-odd rule
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const salsa::Vec2 a = poly[i], b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

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
    if (!(map.bounds.max.x > map.bounds.min.x && map.bounds.max.y > map.bounds.min.y))
      fail("bounds.max", salsa::format::point(map.bounds.max) + " must be greater than bounds.min " + salsa::format::point(map.bounds.min));

    map.obstacles = polylines(root, "obstacles", "polygon", 3, map.bounds);
    map.hollow = polylines(root, "hollow", "outline", 3, map.bounds);
    map.lines = polylines(root, "lines", "line", 2, map.bounds);

    map.spawn = root.contains("spawn") ? point(root["spawn"], "spawn") : map.bounds.centre();
    if (!map.bounds.contains(map.spawn))
      fail("spawn", salsa::format::point(map.spawn) + " is outside " + bounds_text(map.bounds));
    for (std::size_t i = 0; i < map.obstacles.size(); ++i)
      if (inside_polygon(map.spawn, map.obstacles[i]))
        fail("spawn", salsa::format::point(map.spawn) +
                          (root.contains("spawn") ? "" : " (the default, centre of the bounds)") +
                          " is inside obstacles[" + std::to_string(i) + "]; drones must start in free space");
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

  static std::string bounds_text(const salsa::Rect& b) {
    return "the bounds (" + salsa::format::rect(b) + ")";
  }

  std::vector<salsa::Polyline> polylines(const json& root, const std::string& key, const std::string& what,
                                         std::size_t min_points, const salsa::Rect& bounds) const {
    std::vector<salsa::Polyline> out;
    if (!root.contains(key)) return out;
    const json& list = root[key];
    if (!list.is_array())
      fail(key, "expected an array of " + what + "s (arrays of [x, y]), got " + shown(list));
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string field = key + "[" + std::to_string(i) + "]";
      if (!list[i].is_array()) fail(field, "expected an array of points [x, y], got " + shown(list[i]));
      salsa::Polyline& pts = out.emplace_back();
      for (std::size_t j = 0; j < list[i].size(); ++j) {
        const std::string at = field + "[" + std::to_string(j) + "]";
        pts.push_back(point(list[i][j], at));
        if (!bounds.contains(pts.back())) fail(at, salsa::format::point(pts.back()) + " is outside " + bounds_text(bounds));
      }
      // A closed outline may repeat its first point at the end; the closing edge is implied anyway.
      if (min_points == 3 && pts.size() > 1 && pts.front() == pts.back()) pts.pop_back();
      if (pts.size() < min_points)
        fail(field, what + " needs at least " + std::to_string(min_points) + " points, got " +
                        std::to_string(pts.size()));
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
