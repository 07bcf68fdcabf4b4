// Maps read from JSON files; the format is documented in docs/maps.md. Every error is a MapError of
// one line naming the file, the field, the offending value and what is allowed.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>
#include <salsa/sdk.hpp>

namespace {

using nlohmann::json;

std::string number(double v) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return {buf, end};
}
std::string text(salsa::Vec2 p) {  // appended, not "[" + ...: GCC 12 -O3 warns (-Wrestrict) on that
  std::string s = "[";
  s += number(p.x);
  s += ", ";
  s += number(p.y);
  return s += ']';
}
std::string shown(const json& j) {  // a value quoted in a message, cut so the message stays one line
  std::string s = j.dump();
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

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
        fail("", "unknown key '" + key + "' (allowed: bounds, spawn, obstacles, hollow, lines)");

    salsa::MapData map;
    if (!root.contains("bounds")) fail("bounds", "missing; expected {\"min\": [x, y], \"max\": [x, y]}");
    const json& bounds = root["bounds"];
    if (!bounds.is_object())
      fail("bounds", "expected {\"min\": [x, y], \"max\": [x, y]}, got " + shown(bounds));
    for (const auto& [key, value] : bounds.items())
      if (key != "min" && key != "max") fail("bounds", "unknown key '" + key + "' (allowed: min, max)");
    if (!bounds.contains("min") || !bounds.contains("max")) fail("bounds", "needs both \"min\" and \"max\"");
    map.bounds = {point(bounds["min"], "bounds.min"), point(bounds["max"], "bounds.max")};
    if (!(map.bounds.max.x > map.bounds.min.x && map.bounds.max.y > map.bounds.min.y))
      fail("bounds.max", text(map.bounds.max) + " must be greater than bounds.min " + text(map.bounds.min));

    map.obstacles = polylines(root, "obstacles", "polygon", 3, map.bounds);
    map.hollow = polylines(root, "hollow", "outline", 3, map.bounds);
    map.lines = polylines(root, "lines", "line", 2, map.bounds);

    map.spawn = root.contains("spawn") ? point(root["spawn"], "spawn") : map.bounds.centre();
    if (!map.bounds.contains(map.spawn))
      fail("spawn", text(map.spawn) + " is outside " + bounds_text(map.bounds));
    for (std::size_t i = 0; i < map.obstacles.size(); ++i)
      if (inside_polygon(map.spawn, map.obstacles[i]))
        fail("spawn", text(map.spawn) +
                          (root.contains("spawn") ? "" : " (the default, centre of the bounds)") +
                          " is inside obstacles[" + std::to_string(i) + "]; drones must start in free space");
    return map;
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw salsa::MapError(file_ + ": " + (field.empty() ? "" : field + ": ") + what);
  }

  json parse() const {
    if (std::error_code ec; std::filesystem::is_directory(file_, ec))
      fail("", "is a directory, not a map file");
    std::ifstream in(file_, std::ios::binary);
    if (!in) fail("", "cannot open file");
    std::ostringstream buffer;
    buffer << in.rdbuf();
    const std::string content = buffer.str();
    try {
      return json::parse(content);
    } catch (const json::parse_error& e) {
      // e.byte is the 1-based offset of the offending byte (size + 1 at the end of input).
      const std::size_t offset = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, content.size());
      const auto end = content.begin() + static_cast<std::ptrdiff_t>(offset);
      const auto line = 1 + std::count(content.begin(), end, '\n');
      const auto column = 1 + (end - std::find(std::make_reverse_iterator(end), content.rend(), '\n').base());
      fail("", "invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " +
                   parser_text(e));
    } catch (const json::exception& e) {  // e.g. a number too large for a double; no position given
      fail("", "invalid JSON: " + parser_text(e));
    }
  }

  // The parser's message without its "[json.exception.parse_error.101] parse error at line 3, column 7: ".
  static std::string parser_text(const json::exception& e) {
    std::string s = e.what();
    if (const auto at = s.find("] "); at != std::string::npos) s.erase(0, at + 2);
    if (const auto at = s.find(": "); s.starts_with("parse error") && at != std::string::npos)
      s.erase(0, at + 2);
    return s;
  }

  salsa::Vec2 point(const json& j, const std::string& field) const {
    if (!j.is_array() || j.size() != 2 || !j[0].is_number() || !j[1].is_number())
      fail(field, "expected a point [x, y] of two numbers, got " + shown(j));
    const salsa::Vec2 p{j[0].get<double>(), j[1].get<double>()};
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      fail(field, "coordinates must be finite numbers, got " + shown(j));
    return p;
  }

  static std::string bounds_text(const salsa::Rect& b) {
    return "the bounds (min " + text(b.min) + ", max " + text(b.max) + ")";
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
        if (!bounds.contains(pts.back())) fail(at, text(pts.back()) + " is outside " + bounds_text(bounds));
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
