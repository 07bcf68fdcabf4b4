#include "salsa/core/static_geometry.hpp"

#include <algorithm>
#include <cmath>

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

bool StaticGeometry::is_free(Vec2 p, double clearance) const {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(clearance)) return false;
  if (p.x < bounds_.min.x + clearance || p.x > bounds_.max.x - clearance || p.y < bounds_.min.y + clearance ||
      p.y > bounds_.max.y - clearance)
    return false;
  for (std::size_t i = 0; i < solids_.size(); ++i)
    if (solid_boxes_[i].contains(p) && inside_polygon(p, solids_[i])) return false;
  thread_local std::vector<std::uint32_t> ids;  // called per target placed and per virtual point: no allocation
  candidates(p, clearance, ids);
  return std::none_of(ids.begin(), ids.end(), [&](auto id) { return segment_distance(p, segments_[id]) < clearance; });
}

}  // namespace salsa
