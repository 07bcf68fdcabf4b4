// A metric plugin built by the test suite, as a user would write one: it counts the steps it saw and
// sums the drones' x, and on request throws or names its columns like someone else's. Also a behavior
// flying every drone straight along +x at full speed, for hand-computed coverage and distance.
#include <stdexcept>

#include <salsa/sdk.hpp>

namespace {

class TestMetric final : public salsa::Metric {
 public:
  static salsa::Parameters declare() {
    return {{"throw_at", -1, -1, 1e6, "s", "step() throws from this time on (-1: never)"},
            {"clash", 0, 0, 4, "",
             "0: own names; column named 1: coverage (area_coverage's), 2: time (summary.csv's), 3: targets "
             "(outcome.csv's), 4: 'bad name'",
             1}};
  }
  std::vector<salsa::Column> step_columns() const override {
    const int clash = static_cast<int>(param("clash"));
    return {{clash == 1 ? "coverage" : clash == 2 ? "time" : clash == 4 ? "bad name" : "test_steps", "", "steps seen", 0}};
  }
  std::vector<salsa::Column> final_columns() const override {
    return {{param("clash") == 3 ? "targets" : "test_steps_total", "", "steps seen", 0},
            {"test_never", "s", "always empty", 2}};
  }
  void reset(const salsa::MetricView&) override { steps_ = 0; }
  void step(const salsa::MetricView& world) override {
    if (param("throw_at") >= 0 && world.time() >= param("throw_at")) throw std::runtime_error("test metric threw as asked");
    ++steps_;
  }
  void observe(const salsa::MetricView&, std::span<double> values) override { values[0] = steps_; }
  void finish(const salsa::MetricView&, std::span<double> values) override { values[0] = steps_; }

 private:
  double steps_ = 0;
};

class TestStraight final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    return salsa::Vec2{me.max_speed, 0} - me.velocity;
  }
};

}  // namespace

SALSA_METRIC(TestMetric, "test_metric", "Counts steps; throws or clashes on request")
SALSA_BEHAVIOR(TestStraight, "test_straight", "Every drone flies along +x at full speed")
