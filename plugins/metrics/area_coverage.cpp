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

#include "cell_grid.hpp"

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
    grid_.reset(world, cell_size, salsa_metrics::shortest_camera(world));
    seen_.assign(grid_.size(), 0);
    covered_ = 0;
    last_.clear();
    stamp_moved(world, 0);
  }
  void step(const salsa::MetricView& world) override { stamp_moved(world, grid_.cell() / 2); }
  void observe(const salsa::MetricView& world, std::span<double> values) override {
    stamp_moved(world, 0);
    values[0] = grid_.free_count() ? static_cast<double>(covered_) / static_cast<double>(grid_.free_count()) : 0.0;
  }
  void finish(const salsa::MetricView& world, std::span<double> values) override { observe(world, values); }

 private:
  static constexpr double inf = std::numeric_limits<double>::infinity();

  /// Stamps each flying drone that moved more than `distance` since its last stamp (new drones always);
  /// a landed or failed drone sees nothing.
  void stamp_moved(const salsa::MetricView& world, double distance) {
    const auto positions = world.drone_positions();
    const auto status = world.drone_status();
    const auto groups = world.drone_groups();
    if (last_.size() != positions.size()) last_.resize(positions.size(), {inf, inf});
    for (std::size_t i = 0; i < positions.size(); ++i)
      if (status[i] == salsa::DroneStatus::flying && !((positions[i] - last_[i]).length_squared() <= distance * distance)) {
        grid_.for_each_in_disc(positions[i], world.drone(groups[i]).camera_range, [&](std::size_t c) {
          if (grid_.is_free(c) && !seen_[c]) seen_[c] = 1, ++covered_;
        });
        last_[i] = positions[i];
      }
  }

  salsa_metrics::CellGrid grid_;
  std::vector<std::uint8_t> seen_;  // 1 once a camera covered the cell
  std::size_t covered_ = 0;
  std::vector<salsa::Vec2> last_;  // where each drone was last stamped
};

}  // namespace

SALSA_METRIC(AreaCoverage, "area_coverage", "Fraction of the free area seen by some drone's camera")
