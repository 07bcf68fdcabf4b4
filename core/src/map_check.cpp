#include "salsa/core/map_check.hpp"

#include <algorithm>
#include <cmath>

#include "salsa/core/static_geometry.hpp"

namespace salsa {
namespace {

std::string num(double v) { return Parameter::format(v); }  // the shortest text that reads back
double cross(Vec2 o, Vec2 a, Vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }
int sign(double v) { return (v > 0) - (v < 0); }
bool within(Vec2 a, Vec2 b, Vec2 p) {  // p, collinear with a-b, lies on the segment
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}
std::string text(Vec2 p) {  // appended, not "[" + ...: GCC 12 warns falsely (-Wrestrict) on that
  std::string s = "[";
  return s.append(num(p.x)).append(", ").append(num(p.y)).append("]");
}
std::string bounds_text(const Rect& b) { return "the bounds (min " + text(b.min) + ", max " + text(b.max) + ")"; }

}  // namespace

bool segments_touch(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int d1 = sign(cross(c, d, a)), d2 = sign(cross(c, d, b)), d3 = sign(cross(a, b, c)), d4 = sign(cross(a, b, d));
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && within(c, d, a)) || (d2 == 0 && within(c, d, b)) || (d3 == 0 && within(a, b, c)) ||
         (d4 == 0 && within(a, b, d));
}

// Every pair of edges: a drawn polygon has tens of vertices, and a sweep would be more code than the
// maps the creator edits need.
std::pair<std::size_t, std::size_t> crossing_edges(const Polyline& poly) {
  const std::size_t n = poly.size();
  if (n < 3) return {0, 0};
  auto edge = [&](std::size_t i) { return std::pair{poly[i], poly[(i + 1) % n]}; };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const auto [a, b] = edge(i);
      const auto [c, d] = edge(j);
      const bool neighbours = j == i + 1 || (i == 0 && j == n - 1);
      if (neighbours) {
        // They share a vertex; they cross only by folding back over each other (collinear, overlapping).
        const Vec2 shared = j == i + 1 ? b : a, other_i = j == i + 1 ? a : b, other_j = j == i + 1 ? d : c;
        if (sign(cross(shared, other_i, other_j)) == 0 && (other_i - shared).dot(other_j - shared) > 0) return {i, j};
        continue;
      }
      if (segments_touch(a, b, c, d)) return {i, j};
    }
  return {0, 0};
}

std::vector<MapProblem> map_problems(const MapData& map, double drone_radius) {
  using Part = MapProblem::Part;
  std::vector<MapProblem> out;
  const Rect& b = map.bounds;
  const bool bounds_ok = b.max.x > b.min.x && b.max.y > b.min.y;
  if (!bounds_ok) out.push_back({Part::bounds, 0, "bounds.max", text(b.max) + " must be greater than bounds.min " + text(b.min)});

  auto shapes = [&](const std::vector<Polyline>& list, Part part, const char* key, const char* what, std::size_t min_points) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string field = std::string(key) + "[" + std::to_string(i) + "]";
      const Polyline& pts = list[i];
      if (pts.size() < min_points) {
        out.push_back({part, i, field, std::string(what) + " needs at least " + std::to_string(min_points) + " points, got " + std::to_string(pts.size())});
        continue;
      }
      for (std::size_t k = 0; k < pts.size(); ++k)
        if (bounds_ok && !b.contains(pts[k])) {
          out.push_back({part, i, field + "[" + std::to_string(k) + "]", text(pts[k]) + " is outside " + bounds_text(b)});
          break;  // one line per shape: the rest usually follow from the same drag
        }
      if (min_points == 3)
        if (const auto [e1, e2] = crossing_edges(pts); e1 != e2)
          out.push_back({part, i, field, "edges " + std::to_string(e1) + " and " + std::to_string(e2) + " cross (allowed: a simple shape, no edge crossing another)"});
    }
  };
  shapes(map.obstacles, Part::obstacle, "obstacles", "polygon", 3);
  shapes(map.hollow, Part::hollow, "hollow", "outline", 3);
  shapes(map.lines, Part::line, "lines", "line", 2);

  if (bounds_ok && !b.contains(map.spawn)) {
    out.push_back({Part::spawn, 0, "spawn", text(map.spawn) + " is outside " + bounds_text(b)});
  } else if (bounds_ok) {
    for (std::size_t i = 0; i < map.obstacles.size(); ++i)
      if (map.obstacles[i].size() >= 3 && inside_polygon(map.spawn, map.obstacles[i])) {
        out.push_back({Part::spawn, 0, "spawn", text(map.spawn) + " is inside obstacles[" + std::to_string(i) + "]; drones must start in free space"});
        return out;
      }
    if (out.empty() && !StaticGeometry(map, 50).is_free(map.spawn, drone_radius))  // what load_map_file asks
      out.push_back({Part::spawn, 0, "spawn", text(map.spawn) + " is closer than a drone's radius (" + num(drone_radius) + " m) to a wall; drones must start in free space"});
  }
  return out;
}

}  // namespace salsa
