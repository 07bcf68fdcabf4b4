// Distance flown: the length of each drone's path (the sum of its moves between steps while it flies),
// averaged over the drones.
#include <algorithm>
#include <cstddef>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class DistanceFlown final : public salsa::Metric {
 public:
  std::vector<salsa::Column> step_columns() const override {
    return {{"mean_distance", "m", "mean distance flown per drone so far", 3}};
  }
  std::vector<salsa::Column> final_columns() const override {
    return {{"mean_distance", "m", "mean distance flown per drone", 3}};
  }
  void reset(const salsa::MetricView& world) override {
    const auto p = world.drone_positions();
    last_.assign(p.begin(), p.end());
    total_ = 0;
    drones_ = p.size();
  }
  void step(const salsa::MetricView& world) override {
    const auto p = world.drone_positions();
    if (last_.size() < p.size()) last_.insert(last_.end(), p.begin() + static_cast<std::ptrdiff_t>(last_.size()), p.end());
    last_.resize(p.size());  // drones added start where they are; removed ones keep what they flew
    const auto status = world.drone_status();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (status[i] == salsa::DroneStatus::flying) total_ += (p[i] - last_[i]).length();  // a landed drone is not flying
      last_[i] = p[i];
    }
    drones_ = std::max(drones_, p.size());
  }
  void observe(const salsa::MetricView& world, std::span<double> values) override {
    drones_ = std::max(drones_, world.drone_positions().size());
    values[0] = drones_ ? total_ / static_cast<double>(drones_) : 0.0;
  }
  void finish(const salsa::MetricView& world, std::span<double> values) override { observe(world, values); }

 private:
  std::vector<salsa::Vec2> last_;
  double total_ = 0;        // m, over all drones
  std::size_t drones_ = 0;  // the most drones there were
};

}  // namespace

SALSA_METRIC(DistanceFlown, "distance_flown", "Mean distance flown per drone")
