// Collisions: contacts begun over the whole test, drone–drone and drone–obstacle. summary.csv already
// has a running `collisions` column of salsa's own, so this metric adds only the final count.
#include <salsa/sdk.hpp>

namespace {

class Collisions final : public salsa::Metric {
 public:
  std::vector<salsa::Column> final_columns() const override {
    return {{"collisions", "", "contacts begun, drone–drone and drone–obstacle", 0}};
  }
  void finish(const salsa::MetricView& world, std::span<double> values) override {
    values[0] = static_cast<double>(world.collisions());
  }
};

}  // namespace

SALSA_METRIC(Collisions, "collisions", "Count of collisions (drone–drone and drone–obstacle)")
