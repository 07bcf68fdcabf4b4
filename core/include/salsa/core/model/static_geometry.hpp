#pragma once
// The map's static geometry (walls and obstacles) as segments in a uniform grid: free-space tests for
// placement and the obstacle rays of every drone, without touching Box2D or scanning all segments.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "salsa/map.hpp"
#include "salsa/world.hpp"

namespace salsa {

struct Segment {
  Vec2 a, b;
};

class StaticGeometry {
 public:
  StaticGeometry() = default;
  /// `cell_size` m: about the longest query (the obstacle range) keeps queries to a few cells.
  StaticGeometry(const MapData& map, double cell_size);

  const Rect& bounds() const { return bounds_; }
  std::span<const Segment> segments() const { return segments_; }
  /// Cells looked at while filing the segments into the grid: the index's build cost, which tests
  /// check grows with the segments' lengths, not their bounding boxes' areas.
  std::size_t cells_examined() const { return cells_examined_; }

  /// Inside bounds by `clearance` m, outside every solid obstacle, and farther than `clearance`
  /// from every wall segment. Never for a non-finite point or clearance. The obstacles must lie within
  /// the bounds (check_map): they are found through the grid over the bounds, not one by one.
  bool is_free(Vec2 p, double clearance) const;
  /// Nearest hit on the segment from `from` to `to`.
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const;
  /// Whether a wall or obstacle segment crosses the segment from `a` to `b` (the comm model's line of
  /// sight): only the cells the segment passes are looked at, and the first crossing ends the search.
  bool blocked(Vec2 a, Vec2 b) const;
  /// Segment ids whose cells touch the square of half-side `range` around `p`, each once (in cell
  /// order; ascending when there are many).
  void candidates(Vec2 p, double range, std::vector<std::uint32_t>& out) const;
  /// Nearest hit of a ray from `from` along `direction` (unit) within `range`, among `ids`.
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 direction, double range,
                                      std::span<const std::uint32_t> ids) const;

 private:
  /// fn(cell index) for each cell segment `id` passes.
  /// Returns how many cells it looked at.
  template <class Fn>
  std::size_t cells_of(std::uint32_t id, Fn&& fn) const;
  int col(double x) const { return cell_coord(x - origin_.x, cols_); }
  int row(double y) const { return cell_coord(y - origin_.y, rows_); }
  int cell_coord(double offset, int cells) const {  // clamped in double: far or NaN points cannot overflow the int
    const double c = std::floor(offset / cell_);
    return c >= cells - 1 ? cells - 1 : c >= 0 ? static_cast<int>(c) : 0;
  }

  /// Inside a solid obstacle (as inside_polygon says, within the solid's box), from the grid.
  bool inside_solid(Vec2 p) const;

  Rect bounds_{};
  std::vector<Segment> segments_;
  std::vector<Polyline> solids_;
  std::vector<Rect> solid_boxes_;
  double cell_ = 1;
  Vec2 origin_;
  int cols_ = 0, rows_ = 0;
  std::vector<std::uint32_t> cell_start_;  ///< cell c's ids are cell_ids_[cell_start_[c] .. cell_start_[c + 1])
  std::vector<std::uint32_t> cell_ids_;
  std::size_t cells_examined_ = 0;
  std::uint32_t solid_end_ = 4;            ///< segments [4, solid_end_) are the solids' edges
  std::vector<std::uint32_t> small_start_, small_ids_;  ///< per cell, the small solids whose box covers it
  std::vector<std::uint32_t> solid_of_;    ///< the solid of edge id 4 + k (large solids' edges)
  std::vector<std::uint32_t> solid_start_, solid_ids_;  ///< the large solids' edges alone, filed like cell_ids_
};

/// Distance along the ray p + t·d (t ≥ 0, |d| = 1) to segment s, if it crosses it within `range`.
std::optional<double> ray_segment(Vec2 p, Vec2 d, double range, const Segment& s);
/// Whether p is inside the closed polygon (even–odd rule).
bool inside_polygon(Vec2 p, const Polyline& polygon);
double segment_distance(Vec2 p, const Segment& s);

}  // namespace salsa
