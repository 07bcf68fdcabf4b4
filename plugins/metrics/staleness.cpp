// Staleness: how long ago, on average over the free map area, some flying drone's camera last saw each
// place: the measure of a monitoring task, where ground seen once must be seen again. On area_coverage's
// grid of cells, each flying drone marks the cells within its camera range as seen now, every step (a
// drone hovering over a cell keeps it fresh); a cell never seen counts from the start. The mean is kept
// as a running sum, so a step costs O(cells per camera disc × drones) and a row O(1).
#include <cstdint>
#include <vector>

#include <salsa/sdk.hpp>

#include "cell_grid.hpp"

namespace {

class Staleness final : public salsa::Metric {
  salsa::Param cell_size{this, "cell_size", 0.0, 0.0, 1000.0, "m",
                         "grid cell edge; 0: a quarter of the camera range (larger if the map would need over 2^24 cells)", 0.05};

 public:
  std::vector<salsa::Column> step_columns() const override {
    return {{"staleness", "s", "mean over the free area of the time since a camera last saw it", 3}};
  }
  std::vector<salsa::Column> final_columns() const override {
    return {{"staleness", "s", "mean over the free area of the time since a camera last saw it, at the end", 3},
            {"mean_staleness", "s", "staleness averaged over the test's time (lower: the area is watched better)", 3}};
  }

  void reset(const salsa::MetricView& world) override {
    grid_.reset(world, cell_size, salsa_metrics::shortest_camera(world));
    start_ = world.time();
    last_seen_.assign(grid_.size(), start_);
    sum_last_ = start_ * static_cast<double>(grid_.free_count());
    integral_ = 0;
    stamp(world);
  }
  void step(const salsa::MetricView& world) override {
    stamp(world);
    integral_ += now(world) * world.dt();
  }
  void observe(const salsa::MetricView& world, std::span<double> values) override { values[0] = now(world); }
  void finish(const salsa::MetricView& world, std::span<double> values) override {
    values[0] = now(world);
    const double elapsed = world.time() - start_;
    values[1] = elapsed > 0 ? integral_ / elapsed : 0.0;
  }

 private:
  /// The mean age of the free cells now (s).
  double now(const salsa::MetricView& world) const {
    const auto n = static_cast<double>(grid_.free_count());
    return n > 0 ? world.time() - sum_last_ / n : 0.0;
  }
  /// Every flying drone's camera disc is seen now; a landed or failed drone sees nothing.
  void stamp(const salsa::MetricView& world) {
    const double t = world.time();
    const auto positions = world.drone_positions();
    const auto status = world.drone_status();
    const auto groups = world.drone_groups();
    for (std::size_t i = 0; i < positions.size(); ++i)
      if (status[i] == salsa::DroneStatus::flying)
        grid_.for_each_in_disc(positions[i], world.drone(groups[i]).camera_range, [&](std::size_t c) {
          if (grid_.is_free(c)) sum_last_ += t - last_seen_[c], last_seen_[c] = t;
        });
  }

  salsa_metrics::CellGrid grid_;
  std::vector<double> last_seen_;  // s, per cell
  double start_ = 0, sum_last_ = 0, integral_ = 0;
};

}  // namespace

SALSA_METRIC(Staleness, "staleness", "Mean time since the free area was last seen: monitoring with revisits")
