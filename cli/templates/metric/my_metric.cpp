// my_metric: a salsa metric. The swarm's polarisation (0: the drones' headings cancel out, 1: all fly
// the same way) at each row of a test's summary.csv, and its mean over every step in outcome.csv.
// A test lists it in "metrics"; calls come from the stepping thread: reset at time 0, step after
// every step, observe at each logged row, finish once at the end.
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class MyMetric final : public salsa::Metric {
  // Name, default, min, max, unit, meaning; it reads as a double.
  salsa::Param min_speed{this, "min_speed", 0.1, 0.0, 100.0, "m/s", "drones slower than this count as at rest"};

 public:
  std::vector<salsa::Column> step_columns() const override {  // name, unit, meaning, decimals
    return {{"polarisation", "", "length of the moving drones' mean unit velocity (1: all fly the same way)", 3}};
  }
  std::vector<salsa::Column> final_columns() const override {
    return {{"mean_polarisation", "", "polarisation averaged over every step", 3}};
  }
  void reset(const salsa::MetricView&) override { sum_ = 0, steps_ = 0; }
  void step(const salsa::MetricView& world) override {  // 60 times per simulated second: keep it cheap
    if (const double p = polarisation(world); std::isfinite(p)) sum_ += p, ++steps_;
  }
  void observe(const salsa::MetricView& world, std::span<double> values) override { values[0] = polarisation(world); }
  void finish(const salsa::MetricView&, std::span<double> values) override {
    if (steps_ > 0) values[0] = sum_ / static_cast<double>(steps_);  // else no_value: an empty field
  }

 private:
  double polarisation(const salsa::MetricView& world) const {
    salsa::Vec2 sum;
    std::size_t moving = 0;
    for (salsa::Vec2 v : world.drone_velocities())
      if (!v.is_zero() && v.length() > min_speed) sum += v.with_length(1), ++moving;
    return moving > 0 ? sum.length() / static_cast<double>(moving) : salsa::no_value;
  }
  double sum_ = 0;
  std::size_t steps_ = 0;  // steps with a moving drone
};

}  // namespace

SALSA_METRIC(MyMetric, "my_metric", "Polarisation of the swarm: 1 when all fly the same way")
