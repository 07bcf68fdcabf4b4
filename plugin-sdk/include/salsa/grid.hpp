#pragma once
// A uniform grid over points for fixed-radius neighbour queries: built in O(N) by counting sort,
// queried in O(points in the touched cells). The core uses it for drones; plugins may use it for their
// own points (virtual points, pheromone marks) instead of an all-pairs loop.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "salsa/vec2.hpp"

namespace salsa {

class PointGrid {
 public:
  /// Rebuilds over `points` with cells of about `cell_size` m, grown if the points spread so far that
  /// the cells would outnumber the points many times (so any cell size, 0 included, gives at most
  /// 4 × points + 64 cells). Points with a non-finite coordinate are kept but never found. Keeps its
  /// buffers between builds.
  void build(std::span<const Vec2> points, double cell_size) {
    const std::size_t n = points.size();
    Rect box{{0, 0}, {0, 0}};
    bool first = true;
    for (Vec2 p : points) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
      if (first) {
        box = {p, p};
        first = false;
      }
      box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y)};
      box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y)};
    }
    cell_ = cell_size > 1e-9 ? cell_size : 1e-9;  // NaN too
    const double max_cells = 4.0 * static_cast<double>(n) + 64;
    if ((box.width() / cell_ + 1) * (box.height() / cell_ + 1) > max_cells)
      cell_ = std::max(cell_, std::sqrt(box.area() / max_cells) * 1.5);
    while ((box.width() / cell_ + 1) * (box.height() / cell_ + 1) > max_cells) cell_ *= 1.5;
    origin_ = box.min;
    cols_ = static_cast<int>(box.width() / cell_) + 1;
    rows_ = static_cast<int>(box.height() / cell_) + 1;

    start_.assign(static_cast<std::size_t>(cols_) * rows_ + 1, 0);
    cell_of_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      cell_of_[i] = cell_index(points[i]);
      ++start_[cell_of_[i] + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    fill_ = start_;
    items_.resize(n);
    sorted_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {  // stable: ascending index within a cell
      const std::uint32_t slot = fill_[cell_of_[i]]++;
      items_[slot] = static_cast<std::uint32_t>(i);
      sorted_[slot] = points[i];
    }
  }

  /// Calls `fn(index, position, distance_squared)` for every point with distance < radius from `p`
  /// (strictly), in a fixed order (cell by cell, ascending index within a cell).
  template <class Fn>
  void query(Vec2 p, double radius, Fn&& fn) const {
    const double r2 = radius * radius;
    const auto [x0, x1, y0, y1] = cells_touched(p, radius);
    if (x0 > x1 || y0 > y1) return;
    for (int y = y0; y <= y1; ++y) {
      const std::size_t row = static_cast<std::size_t>(y) * cols_;
      for (std::uint32_t k = start_[row + x0], end = start_[row + x1 + 1]; k < end; ++k) {
        const double d2 = distance_squared(sorted_[k], p);
        if (d2 < r2) fn(items_[k], sorted_[k], d2);
      }
    }
  }

  struct Hit {
    std::uint32_t index;
    double distance_squared;
  };
  /// The same points as `query`, in the same order, appended to `out`. Written without a branch per
  /// point (about half the candidates are rejected, so a branch would mispredict half the time).
  void gather(Vec2 p, double radius, std::vector<Hit>& out) const {
    const double r2 = radius * radius;
    const auto [x0, x1, y0, y1] = cells_touched(p, radius);
    if (x0 > x1 || y0 > y1) return;
    std::size_t n = out.size();
    for (int y = y0; y <= y1; ++y) {
      const std::size_t row = static_cast<std::size_t>(y) * cols_;
      const std::uint32_t begin = start_[row + x0], end = start_[row + x1 + 1];
      out.resize(n + (end - begin));
      Hit* slot = out.data();
      for (std::uint32_t k = begin; k < end; ++k) {
        const double d2 = distance_squared(sorted_[k], p);
        slot[n] = {items_[k], d2};
        n += d2 < r2;
      }
    }
    out.resize(n);
  }

  std::size_t size() const { return items_.size(); }
  /// Point indices in cell order: visiting points in this order keeps neighbouring work in cache.
  std::span<const std::uint32_t> cell_order() const { return items_; }
  double cell_size() const { return cell_; }

 private:
  struct CellRange {
    int x0, x1, y0, y1;
  };
  /// Cells the square around the query disc touches; empty (x0 > x1) when it misses the grid, so that
  /// start_ is never read past its end.
  CellRange cells_touched(Vec2 p, double radius) const {
    if (items_.empty()) return {0, -1, 0, -1};
    return {std::max(0, cell_coord(p.x - radius - origin_.x)), std::min(cols_ - 1, cell_coord(p.x + radius - origin_.x)),
            std::max(0, cell_coord(p.y - radius - origin_.y)), std::min(rows_ - 1, cell_coord(p.y + radius - origin_.y))};
  }
  int cell_coord(double offset) const {
    // Clamped in double first so far-away query points cannot overflow the int; NaN goes to -1.
    const double c = std::floor(offset / cell_);
    return c >= 2.0e9 ? 2'000'000'000 : c >= -1.0 ? static_cast<int>(c) : -1;
  }
  std::uint32_t cell_index(Vec2 p) const {
    const int cx = std::clamp(cell_coord(p.x - origin_.x), 0, cols_ - 1);
    const int cy = std::clamp(cell_coord(p.y - origin_.y), 0, rows_ - 1);
    return static_cast<std::uint32_t>(cy * cols_ + cx);
  }

  double cell_ = 1;
  Vec2 origin_;
  int cols_ = 0, rows_ = 0;
  std::vector<std::uint32_t> start_, fill_, cell_of_, items_;
  std::vector<Vec2> sorted_;
};

}  // namespace salsa
