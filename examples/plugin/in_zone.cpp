// in_zone.cpp: a metric. Per logged row, the drones within `radius` of the map's centre; at the end,
// the longest time any drone stayed there.
#include <algorithm>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class InZone final : public salsa::Metric {
  salsa::Param radius{this, "radius", 50.0, 1.0, 1e4, "m", "zone radius around the map centre"};
  std::vector<double> stay_;  // s: each drone's current stay
  double longest_ = 0;

  bool inside(const salsa::MetricView& world, salsa::Vec2 p) const {
    return salsa::distance(p, world.bounds().centre()) < radius;
  }

 public:
  std::vector<salsa::Column> step_columns() const override { return {{"in_zone", "", "drones in the zone", 0}}; }
  std::vector<salsa::Column> final_columns() const override {
    return {{"longest_in_zone", "s", "longest stay of a drone", 2}};
  }
  void reset(const salsa::MetricView& world) override {  // time 0: drones spawned, targets placed
    stay_.assign(world.drone_positions().size(), 0);
    longest_ = 0;
  }
  void step(const salsa::MetricView& world) override {  // after every step: keep it cheap
    const auto p = world.drone_positions();
    stay_.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      stay_[i] = inside(world, p[i]) ? stay_[i] + world.dt() : 0;
      longest_ = std::max(longest_, stay_[i]);
    }
  }
  void observe(const salsa::MetricView& world, std::span<double> values) override {  // each logged row
    values[0] = static_cast<double>(std::ranges::count_if(world.drone_positions(), [&](salsa::Vec2 p) { return inside(world, p); }));
  }
  void finish(const salsa::MetricView&, std::span<double> values) override { values[0] = longest_; }
};

}  // namespace

SALSA_METRIC(InZone, "in_zone", "Drones near the map centre, and the longest stay")
