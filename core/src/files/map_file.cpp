#include "salsa/core/files/map_file.hpp"

#include <charconv>

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
