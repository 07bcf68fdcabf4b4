#include "salsa/core/model/map_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "format.hpp"
#include "salsa/core/model/static_geometry.hpp"

namespace salsa {
namespace {

double cross(Vec2 o, Vec2 a, Vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }
int sign(double v) { return (v > 0) - (v < 0); }
bool within(Vec2 a, Vec2 b, Vec2 p) {  // p, collinear with a-b, lies on the segment
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}
std::string bounds_text(const Rect& b) { return "the bounds (" + format::rect(b) + ")"; }

}  // namespace

bool segments_touch(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int d1 = sign(cross(c, d, a)), d2 = sign(cross(c, d, b)), d3 = sign(cross(a, b, c)), d4 = sign(cross(a, b, d));
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && within(c, d, a)) || (d2 == 0 && within(c, d, b)) || (d3 == 0 && within(a, b, c)) ||
         (d4 == 0 && within(a, b, d));
}

namespace {

/// Neighbours i and j (j == i + 1, or i == 0 and j == n - 1) share a vertex; they cross only by folding
/// back over each other (collinear, overlapping).
bool folds_back(const Polyline& poly, std::size_t i, std::size_t j) {
  const std::size_t n = poly.size();
  const Vec2 a = poly[i], b = poly[(i + 1) % n], c = poly[j], d = poly[(j + 1) % n];
  const Vec2 shared = j == i + 1 ? b : a, other_i = j == i + 1 ? a : b, other_j = j == i + 1 ? d : c;
  return sign(cross(shared, other_i, other_j)) == 0 && (other_i - shared).dot(other_j - shared) > 0;
}
bool edges_cross(const Polyline& poly, std::size_t i, std::size_t j) {  // i < j
  const std::size_t n = poly.size();
  if (j == i + 1 || (i == 0 && j == n - 1)) return folds_back(poly, i, j);
  return segments_touch(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]);
}

}  // namespace

// Small polygons (what the creator's hand draws): every pair. Larger ones (a file may hold 10^6
// vertices): the edges go into a grid of about one cell per edge over the polygon's box, and only edges
// whose boxes share a cell are compared, each pair once, in the first cell they share. Every crossing
// pair is found either way, so the first (i, j) is the same.
std::pair<std::size_t, std::size_t> crossing_edges(const Polyline& poly) {
  const std::size_t n = poly.size();
  if (n < 3) return {0, 0};
  if (n <= 64) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        if (edges_cross(poly, i, j)) return {i, j};
    return {0, 0};
  }
  Rect box{poly[0], poly[0]};
  for (Vec2 p : poly) {
    box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y)};
    box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y)};
  }
  const auto side = static_cast<std::uint32_t>(std::clamp(std::sqrt(static_cast<double>(n)), 1.0, 2048.0));
  // In [0, side): a fraction of the box, so huge coordinates cannot overflow (NaN lands in cell 0).
  auto cell = [&](double v, double lo, double hi) -> std::uint32_t {
    const double f = hi > lo ? (v - lo) / (hi - lo) : 0.0;
    const double c = std::floor(f * side);
    return c >= side - 1 ? side - 1 : c >= 0 ? static_cast<std::uint32_t>(c) : 0;
  };
  struct Span {
    std::uint32_t x0, x1, y0, y1;
  };
  std::vector<Span> spans(n);
  std::vector<std::uint32_t> start(std::size_t{side} * side + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = poly[i], b = poly[(i + 1) % n];
    Span& s = spans[i];
    s = {cell(std::min(a.x, b.x), box.min.x, box.max.x), cell(std::max(a.x, b.x), box.min.x, box.max.x),
         cell(std::min(a.y, b.y), box.min.y, box.max.y), cell(std::max(a.y, b.y), box.min.y, box.max.y)};
    for (std::uint32_t y = s.y0; y <= s.y1; ++y)
      for (std::uint32_t x = s.x0; x <= s.x1; ++x) ++start[std::size_t{y} * side + x + 1];
  }
  for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<std::uint32_t> ids(start.back());
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t y = spans[i].y0; y <= spans[i].y1; ++y)
        for (std::uint32_t x = spans[i].x0; x <= spans[i].x1; ++x) ids[fill[std::size_t{y} * side + x]++] = i;
  }
  std::pair<std::size_t, std::size_t> first{n, n};
  for (std::uint32_t y = 0; y < side; ++y)
    for (std::uint32_t x = 0; x < side; ++x) {
      const std::size_t c = std::size_t{y} * side + x;
      for (std::uint32_t k = start[c]; k < start[c + 1]; ++k)
        for (std::uint32_t l = k + 1; l < start[c + 1]; ++l) {
          const std::uint32_t i = ids[k], j = ids[l];  // ascending within a cell
          const Span &si = spans[i], &sj = spans[j];
          if (std::max(si.x0, sj.x0) != x || std::max(si.y0, sj.y0) != y) continue;  // compared in an earlier cell
          if (std::pair<std::size_t, std::size_t>{i, j} < first && edges_cross(poly, i, j)) first = {i, j};
        }
    }
  return first.first == n ? std::pair<std::size_t, std::size_t>{0, 0} : first;
}

std::vector<MapProblem> map_problems(const MapData& map, double drone_radius, MapRules rules, std::size_t most) {
  using Part = MapProblem::Part;
  std::vector<MapProblem> out;
  auto add = [&](MapProblem p) {
    out.push_back(std::move(p));
    return out.size() >= most;
  };
  const Rect& b = map.bounds;
  const bool finite_bounds = b.min.finite() && b.max.finite();
  const bool ordered = finite_bounds && b.max.x > b.min.x && b.max.y > b.min.y;
  // Every size derived from the map (grids of cells, the heat map, coverage) divides its extent.
  const bool extent_ok = std::isfinite(b.width()) && std::isfinite(b.height());
  const bool bounds_ok = ordered && extent_ok;
  if (!finite_bounds) {
    const bool min_ok = b.min.finite();
    if (add({Part::bounds, 0, min_ok ? "bounds.max" : "bounds.min",
             format::point(min_ok ? b.max : b.min) + " is not finite (allowed: finite corners, max greater than min on both axes)"}))
      return out;
  } else if (!ordered) {
    if (add({Part::bounds, 0, "bounds.max", format::point(b.max) + " must be greater than bounds.min " + format::point(b.min)})) return out;
  } else if (!extent_ok) {
    if (add({Part::bounds, 0, "bounds", format::rect(b) + " span " + format::number(b.width()) + " × " +
                                          format::number(b.height()) + " m, beyond a double (allowed: max − min below 1.7e308 on both axes)"}))
      return out;
  }

  auto shapes = [&](const std::vector<Polyline>& list, Part part, const char* key, const char* what, std::size_t min_points) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string field = std::string(key) + "[" + std::to_string(i) + "]";
      const Polyline& pts = list[i];
      if (pts.size() < min_points) {
        if (add({part, i, field, std::string(what) + " needs at least " + std::to_string(min_points) + " points, got " + std::to_string(pts.size())}))
          return true;
        continue;
      }
      bool points_finite = true;
      for (std::size_t k = 0; k < pts.size(); ++k) {
        if (!pts[k].finite()) {
          points_finite = false;
          if (add({part, i, field + "[" + std::to_string(k) + "]",
                   format::point(pts[k]) + " is not finite (allowed: a point within " + (bounds_ok ? bounds_text(b) : "the bounds") + ")"}))
            return true;
          break;  // one line per shape: the rest usually follow from the same drag
        }
        if (bounds_ok && !b.contains(pts[k])) {
          if (add({part, i, field + "[" + std::to_string(k) + "]", format::point(pts[k]) + " is outside " + bounds_text(b)})) return true;
          break;
        }
      }
      if (rules == MapRules::drawing && min_points == 3 && points_finite)
        if (const auto [e1, e2] = crossing_edges(pts); e1 != e2)
          if (add({part, i, field, "edges " + std::to_string(e1) + " and " + std::to_string(e2) + " cross (allowed: a simple shape, no edge crossing another)"}))
            return true;
    }
    return false;
  };
  if (shapes(map.obstacles, Part::obstacle, "obstacles", "polygon", 3)) return out;
  if (shapes(map.hollow, Part::hollow, "hollow", "outline", 3)) return out;
  if (shapes(map.lines, Part::line, "lines", "line", 2)) return out;

  if (!map.spawn.finite()) {
    add({Part::spawn, 0, "spawn", format::point(map.spawn) + " is not finite (allowed: a point in free space within the bounds)"});
    return out;
  }
  if (rules == MapRules::structure) return out;  // the simulation moves a spawn point outside the walls inside
  if (bounds_ok && !b.contains(map.spawn)) {
    add({Part::spawn, 0, "spawn", format::point(map.spawn) + " is outside " + bounds_text(b)});
  } else if (bounds_ok) {
    for (std::size_t i = 0; i < map.obstacles.size(); ++i)
      if (map.obstacles[i].size() >= 3 && inside_polygon(map.spawn, map.obstacles[i])) {
        add({Part::spawn, 0, "spawn", format::point(map.spawn) + " is inside obstacles[" + std::to_string(i) + "]; drones must start in free space"});
        return out;
      }
    if (out.empty() && !StaticGeometry(map, 50).is_free(map.spawn, drone_radius))  // what load_map_file asks
      add({Part::spawn, 0, "spawn", format::point(map.spawn) + " is closer than a drone's radius (" + format::number(drone_radius) + " m) to a wall; drones must start in free space"});
  }
  return out;
}

}  // namespace salsa
