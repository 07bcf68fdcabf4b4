// Area coverage: the fraction of the free map area that has been within some flying drone's camera range,
// on a grid of cells (a cell is free when its centre is, and covered once its centre has been within
// camera range of a drone). A drone's disc is stamped whenever it has moved half a cell since its last
// stamp (and at every logged row), so a step costs O(drones) and a stamp O(cells per disc); cells at
// the very edge of the swept band (a sliver of width (cell/2)² / (8 × range)) may be missed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class AreaCoverage final : public salsa::Metric {
  salsa::Param cell_size{this, "cell_size", 0.0, 0.0, 1000.0, "m",
                         "grid cell edge; 0: a quarter of the camera range (larger if the map would need over 2^24 cells)", 0.05};

 public:
  std::vector<salsa::Column> step_columns() const override {
    return {{"coverage", "", "fraction of the free area seen so far (0 to 1)", 6}};
  }
  std::vector<salsa::Column> final_columns() const override { return step_columns(); }

  void reset(const salsa::MetricView& world) override {
    const salsa::Rect b = world.bounds();
    range_ = world.drone().camera_range;  // the cells fit the shortest camera of any group
    for (std::uint32_t g = 1; g < world.group_count(); ++g) range_ = std::min(range_, world.drone(g).camera_range);
    const double side = std::max(b.width(), b.height());
    cell_ = cell_size > 0 ? cell_size.value() : range_ > 0 ? range_ / 4 : side / 1000;
    // A byte per cell: at most 16 MB (the long side too, for a thin map whose area is small).
    cell_ = std::max({cell_, std::sqrt(b.area() / max_cells), side / max_cells});
    if (!(cell_ > 0 && std::isfinite(cell_))) cell_ = side > 0 && std::isfinite(side) ? side : 1;
    origin_ = b.min;
    cols_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(b.width() / cell_)));
    rows_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(b.height() / cell_)));
    // Free cells once, never per step: a block of cells whose centres all lie in one free disc is free
    // at one query (open land is most of a map); other blocks split in four, down to single cells.
    state_.assign(static_cast<std::size_t>(cols_ * rows_), obstacle);
    free_ = covered_ = 0;
    for (std::int64_t r = 0; r < rows_; r += top_block)
      for (std::int64_t c = 0; c < cols_; c += top_block) mark_free(world, c, r, top_block);
    last_.clear();
    stamp_moved(world, 0);
  }
  void step(const salsa::MetricView& world) override { stamp_moved(world, cell_ / 2); }
  void observe(const salsa::MetricView& world, std::span<double> values) override {
    stamp_moved(world, 0);
    values[0] = fraction();
  }
  void finish(const salsa::MetricView& world, std::span<double> values) override { observe(world, values); }

 private:
  static constexpr double max_cells = 1 << 24;
  static constexpr std::int64_t top_block = 64;  // cells per side of the largest block tested at once
  static constexpr double inf = std::numeric_limits<double>::infinity();
  enum : std::uint8_t { obstacle, unseen, seen };

  salsa::Vec2 centre(std::int64_t c, std::int64_t r) const {
    return {origin_.x + (static_cast<double>(c) + 0.5) * cell_, origin_.y + (static_cast<double>(r) + 0.5) * cell_};
  }
  std::size_t index(std::int64_t c, std::int64_t r) const { return static_cast<std::size_t>(r * cols_ + c); }
  double fraction() const { return free_ ? static_cast<double>(covered_) / static_cast<double>(free_) : 0.0; }

  /// Marks the free cells of the block of `size` × `size` cells from (c0, r0) (cut at the grid's edge).
  void mark_free(const salsa::MetricView& world, std::int64_t c0, std::int64_t r0, std::int64_t size) {
    const std::int64_t c1 = std::min(cols_, c0 + size), r1 = std::min(rows_, r0 + size);
    if (c0 >= c1 || r0 >= r1) return;
    const salsa::Vec2 first = centre(c0, r0), last = centre(c1 - 1, r1 - 1);
    const double reach = (last - first).length() / 2;
    if (size == 1 || world.is_free((first + last) / 2, reach * (1 + 1e-9) + 1e-9)) {
      for (std::int64_t r = r0; r < r1; ++r)
        for (std::int64_t c = c0; c < c1; ++c)
          if (size > 1 || world.is_free(centre(c, r), 0)) state_[index(c, r)] = unseen, ++free_;
      return;
    }
    const std::int64_t half = size / 2;
    for (std::int64_t r : {r0, r0 + half})
      for (std::int64_t c : {c0, c0 + half}) mark_free(world, c, r, half);
  }

  /// Stamps each flying drone that moved more than `distance` since its last stamp (new drones always);
  /// a landed or failed drone sees nothing.
  void stamp_moved(const salsa::MetricView& world, double distance) {
    const auto positions = world.drone_positions();
    const auto status = world.drone_status();
    const auto groups = world.drone_groups();
    if (last_.size() != positions.size()) last_.resize(positions.size(), {inf, inf});
    for (std::size_t i = 0; i < positions.size(); ++i)
      if (status[i] == salsa::DroneStatus::flying && !((positions[i] - last_[i]).length_squared() <= distance * distance)) {
        stamp(positions[i], world.drone(groups[i]).camera_range);
        last_[i] = positions[i];
      }
  }

  /// Marks the cells whose centre is within `range` (the drone's camera range) of `p`, row by row.
  void stamp(salsa::Vec2 p, double range) {
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
      std::uint8_t* row = &state_[index(0, static_cast<std::int64_t>(r))];
      for (auto c = static_cast<std::int64_t>(c0); c <= static_cast<std::int64_t>(c1); ++c)
        if (row[c] == unseen) row[c] = seen, ++covered_;
    }
  }

  double range_ = 0, cell_ = 1;
  salsa::Vec2 origin_;
  std::int64_t cols_ = 0, rows_ = 0;
  std::vector<std::uint8_t> state_;
  std::size_t free_ = 0, covered_ = 0;
  std::vector<salsa::Vec2> last_;  // where each drone was last stamped
};

}  // namespace

SALSA_METRIC(AreaCoverage, "area_coverage", "Fraction of the free area seen by some drone's camera")
