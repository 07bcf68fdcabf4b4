#pragma once
// The grid of cells the area metrics (area_coverage, staleness) keep over the map: which cells are free
// (a cell is free when its centre is) and which lie within a camera's disc. One byte-sized state per cell.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <salsa/sdk.hpp>

namespace salsa_metrics {

class CellGrid {
 public:
  static constexpr double max_cells = 1 << 24;  // a cell each: at most 16 MB of states

  /// Lays the grid over the world's bounds: cells of `cell_size` m (0: a quarter of `range`), enlarged
  /// to keep within max_cells; then marks the free cells. `range` is the shortest camera range.
  void reset(const salsa::MetricView& world, double cell_size, double range) {
    const salsa::Rect b = world.bounds();
    const double side = std::max(b.width(), b.height());
    cell_ = cell_size > 0 ? cell_size : range > 0 ? range / 4 : side / 1000;
    // The long side too, for a thin map whose area is small.
    cell_ = std::max({cell_, std::sqrt(b.area() / max_cells), side / max_cells});
    if (!(cell_ > 0 && std::isfinite(cell_))) cell_ = side > 0 && std::isfinite(side) ? side : 1;
    origin_ = b.min;
    cols_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(b.width() / cell_)));
    rows_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(b.height() / cell_)));
    // Free cells once, never per step: a block of cells whose centres all lie in one free disc is free
    // at one query (open land is most of a map); other blocks split in four, down to single cells.
    free_.assign(static_cast<std::size_t>(cols_ * rows_), 0);
    free_count_ = 0;
    for (std::int64_t r = 0; r < rows_; r += top_block)
      for (std::int64_t c = 0; c < cols_; c += top_block) mark_free(world, c, r, top_block);
  }

  double cell() const { return cell_; }
  std::size_t size() const { return free_.size(); }
  std::size_t free_count() const { return free_count_; }
  bool is_free(std::size_t i) const { return free_[i] != 0; }

  /// fn(index) for every cell whose centre is within `range` of `p` (m), row by row.
  template <class Fn>
  void for_each_in_disc(salsa::Vec2 p, double range, Fn&& fn) const {
    // The first and last cell index whose centre lies in [from, to] (m from the origin), clamped.
    auto span = [&](double from, double to, std::int64_t cells) {
      return std::pair{std::max<double>(0, std::ceil(from / cell_ - 0.5)),
                       std::min<double>(static_cast<double>(cells - 1), std::floor(to / cell_ - 0.5))};
    };
    const salsa::Vec2 q = p - origin_;
    if (!std::isfinite(q.x) || !std::isfinite(q.y)) return;
    const auto [r0, r1] = span(q.y - range, q.y + range, rows_);
    for (double r = r0; r <= r1; ++r) {
      const double dy = (r + 0.5) * cell_ - q.y, w2 = range * range - dy * dy;
      if (w2 < 0) continue;
      const double w = std::sqrt(w2);
      const auto [c0, c1] = span(q.x - w, q.x + w, cols_);
      const std::size_t row = index(0, static_cast<std::int64_t>(r));
      for (auto c = static_cast<std::int64_t>(c0); c <= static_cast<std::int64_t>(c1); ++c) fn(row + static_cast<std::size_t>(c));
    }
  }

 private:
  static constexpr std::int64_t top_block = 64;  // cells per side of the largest block tested at once

  salsa::Vec2 centre(std::int64_t c, std::int64_t r) const {
    return {origin_.x + (static_cast<double>(c) + 0.5) * cell_, origin_.y + (static_cast<double>(r) + 0.5) * cell_};
  }
  std::size_t index(std::int64_t c, std::int64_t r) const { return static_cast<std::size_t>(r * cols_ + c); }

  /// Marks the free cells of the block of `size` × `size` cells from (c0, r0) (cut at the grid's edge).
  void mark_free(const salsa::MetricView& world, std::int64_t c0, std::int64_t r0, std::int64_t size) {
    const std::int64_t c1 = std::min(cols_, c0 + size), r1 = std::min(rows_, r0 + size);
    if (c0 >= c1 || r0 >= r1) return;
    const salsa::Vec2 first = centre(c0, r0), last = centre(c1 - 1, r1 - 1);
    const double reach = (last - first).length() / 2;
    if (size == 1 || world.is_free((first + last) / 2, reach * (1 + 1e-9) + 1e-9)) {
      for (std::int64_t r = r0; r < r1; ++r)
        for (std::int64_t c = c0; c < c1; ++c)
          if (size > 1 || world.is_free(centre(c, r), 0)) free_[index(c, r)] = 1, ++free_count_;
      return;
    }
    const std::int64_t half = size / 2;
    for (std::int64_t r : {r0, r0 + half})
      for (std::int64_t c : {c0, c0 + half}) mark_free(world, c, r, half);
  }

  double cell_ = 1;
  salsa::Vec2 origin_;
  std::int64_t cols_ = 0, rows_ = 0;
  std::vector<std::uint8_t> free_;
  std::size_t free_count_ = 0;
};

/// The shortest camera range of the test's groups: the cells fit it.
inline double shortest_camera(const salsa::MetricView& world) {
  double range = world.drone().camera_range;
  for (std::uint32_t g = 1; g < world.group_count(); ++g) range = std::min(range, world.drone(g).camera_range);
  return range;
}

}  // namespace salsa_metrics
