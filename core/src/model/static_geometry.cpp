#include "salsa/core/model/static_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace salsa {

std::optional<double> ray_segment(Vec2 p, Vec2 d, double range, const Segment& s) {
  const Vec2 e = s.b - s.a;
  const double denom = d.cross(e);
  if (denom == 0) return std::nullopt;  // parallel: a grazing ray sees the segment's ends elsewhere
  const Vec2 ap = s.a - p;
  const double t = ap.cross(e) / denom;
  const double u = ap.cross(d) / denom;
  if (t < 0 || t > range || u < 0 || u > 1) return std::nullopt;
  return t;
}

bool inside_polygon(Vec2 p, const Polyline& poly) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 a = poly[i], b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

double segment_distance(Vec2 p, const Segment& s) {
  const Vec2 e = s.b - s.a;
  const double l2 = e.length_squared();
  const double t = l2 > 0 ? std::clamp((p - s.a).dot(e) / l2, 0.0, 1.0) : 0.0;
  return distance(p, s.a + e * t);
}

StaticGeometry::StaticGeometry(const MapData& map, double cell_size) : bounds_(map.bounds) {
  const Rect& b = bounds_;
  // The grid's size comes from the extent: one beyond a double (check_map refuses it) has no grid.
  if (!(std::isfinite(b.width()) && std::isfinite(b.height()) && b.width() >= 0 && b.height() >= 0))
    throw std::invalid_argument("bounds: the map's extent " + std::to_string(b.width()) + " × " + std::to_string(b.height()) +
                                " m is not finite (allowed: max − min finite and ≥ 0 on both axes)");
  segments_ = {{b.min, {b.max.x, b.min.y}}, {{b.max.x, b.min.y}, b.max},
               {b.max, {b.min.x, b.max.y}}, {{b.min.x, b.max.y}, b.min}};
  auto add_loop = [&](const Polyline& pts) {
    for (std::size_t i = 0; i < pts.size(); ++i) segments_.push_back({pts[i], pts[(i + 1) % pts.size()]});
  };
  for (const auto& poly : map.obstacles) {
    add_loop(poly);
    solids_.push_back(poly);
    Rect box{poly[0], poly[0]};
    for (Vec2 p : poly) {
      box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y)};
      box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y)};
    }
    solid_boxes_.push_back(box);
  }
  solid_end_ = static_cast<std::uint32_t>(segments_.size());  // ids [4, solid_end_): edges of solids, in order
  for (const auto& poly : map.hollow) add_loop(poly);
  for (const auto& line : map.lines)
    for (std::size_t i = 0; i + 1 < line.size(); ++i) segments_.push_back({line[i], line[i + 1]});

  // At most ~1M cells however large the map; a little margin so boundary walls fall inside.
  cell_ = std::max({cell_size, b.width() / 1024, b.height() / 1024, 1e-6});
  origin_ = b.min - Vec2{cell_, cell_};
  cols_ = static_cast<int>(b.width() / cell_) + 3;
  rows_ = static_cast<int>(b.height() / cell_) + 3;
  // Each cell's ids, ascending, in one array (counting sort): a query reads a row of cells as one range.
  cell_start_.assign(static_cast<std::size_t>(cols_) * rows_ + 1, 0);
  for (std::uint32_t i = 0; i < segments_.size(); ++i)
    cells_examined_ += cells_of(i, [&](std::size_t c) { ++cell_start_[c + 1]; });
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cell_ids_.resize(cell_start_.back());
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::uint32_t i = 0; i < segments_.size(); ++i) cells_of(i, [&](std::size_t c) { cell_ids_[fill[c]++] = i; });

  // Solids for is_free's inside test. A small one (a box of at most 64 cells, at most 64 vertices: a
  // forest's obstacle) is listed in each cell its box covers and tested as it is; a large one's edges
  // are filed like the segments, and a ray to the right along one row of cells counts its crossings.
  if (solids_.empty()) return;
  std::vector<std::uint32_t> big;
  small_start_.assign(cell_start_.size(), 0);
  auto box_cells = [&](std::uint32_t k, auto&& fn) {
    const Rect& box = solid_boxes_[k];
    for (int y = row(box.min.y); y <= row(box.max.y); ++y)
      for (int x = col(box.min.x); x <= col(box.max.x); ++x) fn(static_cast<std::size_t>(y) * cols_ + x);
  };
  for (std::uint32_t k = 0; k < solids_.size(); ++k) {
    const Rect& box = solid_boxes_[k];
    const double cells = (col(box.max.x) - col(box.min.x) + 1.0) * (row(box.max.y) - row(box.min.y) + 1.0);
    if (cells <= 64 && solids_[k].size() <= 64) box_cells(k, [&](std::size_t c) { ++small_start_[c + 1]; });
    else big.push_back(k);
  }
  for (std::size_t c = 1; c < small_start_.size(); ++c) small_start_[c] += small_start_[c - 1];
  small_ids_.resize(small_start_.back());
  fill.assign(small_start_.begin(), small_start_.end() - 1);
  for (std::uint32_t k = 0, next_big = 0; k < solids_.size(); ++k) {
    if (next_big < big.size() && big[next_big] == k) {
      ++next_big;
      continue;
    }
    box_cells(k, [&](std::size_t c) { small_ids_[fill[c]++] = k; });
  }
  if (big.empty()) return;
  std::vector<std::uint32_t> first_edge(solids_.size() + 1, 4);  // solid k's edges: ids [first_edge[k], first_edge[k + 1])
  for (std::uint32_t k = 0; k < solids_.size(); ++k) first_edge[k + 1] = first_edge[k] + static_cast<std::uint32_t>(solids_[k].size());
  solid_of_.assign(solid_end_ - 4, 0);
  solid_start_.assign(cell_start_.size(), 0);
  for (std::uint32_t k : big)
    for (std::uint32_t i = first_edge[k]; i < first_edge[k + 1]; ++i) {
      solid_of_[i - 4] = k;
      cells_of(i, [&](std::size_t c) { ++solid_start_[c + 1]; });
    }
  for (std::size_t c = 1; c < solid_start_.size(); ++c) solid_start_[c] += solid_start_[c - 1];
  solid_ids_.resize(solid_start_.back());
  fill.assign(solid_start_.begin(), solid_start_.end() - 1);
  for (std::uint32_t k : big)
    for (std::uint32_t i = first_edge[k]; i < first_edge[k + 1]; ++i) cells_of(i, [&](std::size_t c) { solid_ids_[fill[c]++] = i; });
}

bool StaticGeometry::inside_solid(Vec2 p) const {
  // Large solids: inside_polygon(p, solid) for each whose box holds p, answered alike: its even–odd test counts
  // the edges that straddle the line y = p.y and cross it right of p. Those crossings lie in p's row of
  // cells, right of p, and each edge is filed in the cell holding its crossing point (a point of the
  // edge is within half a cell's diagonal of that cell's centre), so each is counted there, once.
  if (solids_.empty() || !bounds_.contains(p)) return false;  // every solid lies within the bounds
  const std::size_t row_first = static_cast<std::size_t>(row(p.y)) * cols_;
  const std::size_t cell = row_first + static_cast<std::size_t>(col(p.x));
  for (std::uint32_t k = small_start_[cell]; k < small_start_[cell + 1]; ++k)
    if (const std::uint32_t s = small_ids_[k]; solid_boxes_[s].contains(p) && inside_polygon(p, solids_[s])) return true;
  if (solid_start_.empty()) return false;  // no large solid
  int x = col(p.x);
  const std::uint32_t end = solid_start_[row_first + cols_];
  thread_local std::vector<std::uint32_t> crossed;  // the solid of each counted crossing
  crossed.clear();
  for (std::uint32_t k = solid_start_[row_first + x]; k < end; ++k) {
    while (solid_start_[row_first + x + 1] <= k) ++x;  // the cell entry k belongs to
    const std::uint32_t id = solid_ids_[k];
    const Segment& s = segments_[id];
    const Vec2 a = s.b, b = s.a;  // inside_polygon's operands: a is the edge's later vertex
    if ((a.y > p.y) == (b.y > p.y)) continue;
    const double cross_x = (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x;
    if (!(p.x < cross_x)) continue;
    // The crossing's cell; kept within the edge's own columns, where rounding may put it an ulp outside.
    const int owner = std::clamp(col(cross_x), col(std::min(a.x, b.x)), col(std::max(a.x, b.x)));
    if (owner == x) crossed.push_back(solid_of_[id - 4]);
  }
  if (crossed.empty()) return false;
  std::sort(crossed.begin(), crossed.end());
  for (std::size_t i = 0; i < crossed.size();) {  // a solid crossed an odd number of times holds p
    std::size_t j = i;
    while (j < crossed.size() && crossed[j] == crossed[i]) ++j;
    if ((j - i) % 2 == 1 && solid_boxes_[crossed[i]].contains(p)) return true;
    i = j;
  }
  return false;
}

template <class Fn>
std::size_t StaticGeometry::cells_of(std::uint32_t id, Fn&& fn) const {
  // The cells of the segment's bounding box that it really passes (within the cell's circumcircle).
  // Row by row, only the columns near the part of the segment inside the row's band are looked at, so a
  // long diagonal costs its length in cells, not its bounding box's area.
  const Segment& s = segments_[id];
  const double reach = cell_ * 0.7072, margin = reach * 1.01;
  const Vec2 d = s.b - s.a;
  std::size_t examined = 0;
  const int x_lo = col(std::min(s.a.x, s.b.x)), x_hi = col(std::max(s.a.x, s.b.x));
  for (int y = row(std::min(s.a.y, s.b.y)); y <= row(std::max(s.a.y, s.b.y)); ++y) {
    const double cy = origin_.y + (y + 0.5) * cell_;
    double t0 = 0, t1 = 1;  // the part of the segment within `margin` of the row's centre line
    if (d.y != 0) {
      const double ta = (cy - margin - s.a.y) / d.y, tb = (cy + margin - s.a.y) / d.y;
      t0 = std::max(0.0, std::min(ta, tb));
      t1 = std::min(1.0, std::max(ta, tb));
      if (t0 > t1) continue;
    } else if (std::abs(s.a.y - cy) > margin) {
      continue;
    }
    const double xa = s.a.x + d.x * t0, xb = s.a.x + d.x * t1;
    for (int x = std::max(x_lo, col(std::min(xa, xb) - margin)), last = std::min(x_hi, col(std::max(xa, xb) + margin)); x <= last; ++x) {
      const Vec2 centre = origin_ + Vec2{x * cell_, y * cell_} + Vec2{cell_ / 2, cell_ / 2};
      ++examined;
      if (segment_distance(centre, s) <= reach) fn(static_cast<std::size_t>(y) * cols_ + x);
    }
  }
  return examined;
}

void StaticGeometry::candidates(Vec2 p, double range, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (cell_start_.empty()) return;
  const int x0 = col(p.x - range), x1 = col(p.x + range), y0 = row(p.y - range), y1 = row(p.y + range);
  for (int y = y0; y <= y1; ++y) {
    const std::size_t first = static_cast<std::size_t>(y) * cols_;
    for (std::uint32_t k = cell_start_[first + x0], end = cell_start_[first + x1 + 1]; k < end; ++k)
      if (const std::uint32_t id = cell_ids_[k]; out.size() > 32 || std::find(out.begin(), out.end(), id) == out.end())
        out.push_back(id);
  }
  if (out.size() > 32) {  // many segments: dedupe by sorting instead
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }
}

std::optional<ObstacleHit> StaticGeometry::ray_cast(Vec2 from, Vec2 direction, double range,
                                                    std::span<const std::uint32_t> ids) const {
  std::optional<double> best;
  for (std::uint32_t id : ids)
    if (auto t = ray_segment(from, direction, range, segments_[id]); t && (!best || *t < *best)) best = t;
  if (!best) return std::nullopt;
  return ObstacleHit{from + direction * *best, *best};
}

std::optional<ObstacleHit> StaticGeometry::ray_cast(Vec2 from, Vec2 to) const {
  const double length = distance(from, to);
  if (length == 0) return std::nullopt;
  std::vector<std::uint32_t> ids;
  candidates((from + to) / 2, length / 2, ids);
  return ray_cast(from, (to - from) / length, length, ids);
}

bool StaticGeometry::blocked(Vec2 a, Vec2 b) const {
  // Segments 0–3 are the bounds, which two points inside them never cross: nothing else, nothing to do.
  if (cell_start_.empty() || segments_.size() <= 4) return false;
  const Vec2 d = b - a;
  const double length = d.length();
  if (!(length > 0) || !std::isfinite(length)) return false;
  const Vec2 unit = d / length;
  // Row by row, the columns of the part of a→b inside the row's band. A crossing point lies in one of
  // those cells, and the segment it is on is filed there (cells_of files a segment in every cell it
  // comes within the cell's circumcircle of), so no crossing is missed.
  for (int y = row(std::min(a.y, b.y)), last_row = row(std::max(a.y, b.y)); y <= last_row; ++y) {
    double t0 = 0, t1 = 1;
    if (d.y != 0) {
      const double band = origin_.y + y * cell_;
      const double ta = (band - a.y) / d.y, tb = (band + cell_ - a.y) / d.y;
      t0 = std::max(0.0, std::min(ta, tb));
      t1 = std::min(1.0, std::max(ta, tb));
      if (t0 > t1) continue;
    }
    const double xa = a.x + d.x * t0, xb = a.x + d.x * t1;
    const std::size_t first = static_cast<std::size_t>(y) * cols_;
    for (std::uint32_t k = cell_start_[first + col(std::min(xa, xb))], end = cell_start_[first + col(std::max(xa, xb)) + 1]; k < end; ++k)
      if (ray_segment(a, unit, length, segments_[cell_ids_[k]])) return true;
  }
  return false;
}

bool StaticGeometry::is_free(Vec2 p, double clearance) const {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(clearance)) return false;
  if (p.x < bounds_.min.x + clearance || p.x > bounds_.max.x - clearance || p.y < bounds_.min.y + clearance ||
      p.y > bounds_.max.y - clearance)
    return false;
  if (inside_solid(p)) return false;
  thread_local std::vector<std::uint32_t> ids;  // called per target placed and per virtual point: no allocation
  candidates(p, clearance, ids);
  return std::none_of(ids.begin(), ids.end(), [&](auto id) { return segment_distance(p, segments_[id]) < clearance; });
}

}  // namespace salsa
