// Time to find 50 %, 90 % and 100 % of the targets: when the ⌈f × targets⌉-th target was found
// (targets.csv's found_time). Empty when never reached, or when the test has no targets.
#include <algorithm>
#include <cstddef>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class TimeToFound final : public salsa::Metric {
 public:
  std::vector<salsa::Column> final_columns() const override {
    return {{"time_to_50", "s", "time when half of the targets had been found", 4},
            {"time_to_90", "s", "time when 90 % of the targets had been found", 4},
            {"time_to_100", "s", "time when every target had been found", 4}};
  }
  void finish(const salsa::MetricView& world, std::span<double> values) override {
    std::vector<double> times;
    for (const salsa::TargetState& t : world.targets())
      if (t.found()) times.push_back(t.found_time);
    std::sort(times.begin(), times.end());
    const std::size_t n = world.targets().size();
    const std::size_t percents[] = {50, 90, 100};
    for (std::size_t i = 0; i < 3; ++i) {
      const std::size_t needed = (percents[i] * n + 99) / 100;  // ⌈p % of n⌉, in whole numbers
      if (n > 0 && times.size() >= needed) values[i] = times[needed - 1];
    }
  }
};

}  // namespace

SALSA_METRIC(TimeToFound, "time_to_found", "Time until 50, 90 and 100 % of the targets were found")
