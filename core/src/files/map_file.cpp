#include "salsa/core/files/map_file.hpp"

#include <charconv>

#include <nlohmann/json.hpp>

#include "salsa/core/files/input_error.hpp"
#include "strict_json.hpp"

namespace salsa {
namespace {

void append_number(std::string& out, double v) {
  if (v == 0) v = 0;  // no "-0": it would read back as the integer 0 anyway
  char text[32];
  out.append(text, std::to_chars(text, text + sizeof text, v).ptr);  // shortest text that reads back exactly
}

void append_point(std::string& out, Vec2 p) {
  out += '[';
  append_number(out, p.x);
  out += ", ";
  append_number(out, p.y);
  out += ']';
}

void append_shapes(std::string& out, const char* key, const std::vector<Polyline>& shapes, bool last) {
  out += "  \"";
  out += key;
  out += "\": [";
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    out += i ? ",\n    [" : "\n    [";
    for (std::size_t j = 0; j < shapes[i].size(); ++j) {
      if (j) out += ", ";
      append_point(out, shapes[i][j]);
    }
    out += ']';
  }
  out += shapes.empty() ? "]" : "\n  ]";
  out += last ? "\n" : ",\n";
}

}  // namespace

MapData read_map_file(const std::filesystem::path& file) {
  using nlohmann::json;
  const std::string name = strict_json::printable(file.string(), 200);
  json j;
  try {
    j = strict_json::read_file<json>(file, "a map file (see docs/maps.md)");
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
  auto point = [&](const json& p, const std::string& at) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw InputError(name + ": " + at + ": " + strict_json::shown(p) + " is not a point [x, y]");
    return Vec2{p[0].get<double>(), p[1].get<double>()};
  };
  if (!j.is_object() || !j.contains("bounds") || !j["bounds"].is_object() || !j["bounds"].contains("min") || !j["bounds"].contains("max"))
    throw InputError(name + ": bounds: missing (a map file has {\"bounds\": {\"min\": [x, y], \"max\": [x, y]}})");
  MapData map;
  map.bounds = {point(j["bounds"]["min"], "bounds.min"), point(j["bounds"]["max"], "bounds.max")};
  if (!(map.bounds.max.x > map.bounds.min.x && map.bounds.max.y > map.bounds.min.y))
    throw InputError(name + ": bounds.max: " + strict_json::shown(j["bounds"]["max"]) + " must be greater than bounds.min " +
                     strict_json::shown(j["bounds"]["min"]));
  map.spawn = j.contains("spawn") ? point(j["spawn"], "spawn") : map.bounds.centre();
  for (auto [key, into] : {std::pair{"obstacles", &map.obstacles}, std::pair{"hollow", &map.hollow}, std::pair{"lines", &map.lines}}) {
    if (!j.contains(key)) continue;
    if (!j[key].is_array()) throw InputError(name + ": " + key + ": " + strict_json::shown(j[key]) + " is not a list of point lists");
    for (std::size_t i = 0; i < j[key].size(); ++i) {
      const json& shape = j[key][i];
      const std::string at = std::string(key) + "[" + std::to_string(i) + "]";
      if (!shape.is_array()) throw InputError(name + ": " + at + ": " + strict_json::shown(shape) + " is not a list of points");
      Polyline line;
      for (std::size_t k = 0; k < shape.size(); ++k) line.push_back(point(shape[k], at + "[" + std::to_string(k) + "]"));
      into->push_back(std::move(line));
    }
  }
  return map;
}

std::string map_json(const MapData& map, Vec2 spawn) {
  std::string out = "{\n  \"bounds\": {\"min\": ";
  append_point(out, map.bounds.min);
  out += ", \"max\": ";
  append_point(out, map.bounds.max);
  out += "},\n  \"spawn\": ";
  append_point(out, spawn);
  out += ",\n";
  append_shapes(out, "obstacles", map.obstacles, false);
  append_shapes(out, "hollow", map.hollow, false);
  append_shapes(out, "lines", map.lines, true);
  return out += "}\n";
}

}  // namespace salsa
