// A behavior that returns a NaN steering from time `at` on: a failure while running, which must be
// reported naming the behavior and the test (exit status 1).
#include <limits>

#include <salsa/sdk.hpp>

namespace {

class TestNan final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() { return {{"at", 0.5, 0.0, 1e6, "s", "time from which decide returns NaN"}}; }
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    if (me.time >= param("at")) return {std::numeric_limits<double>::quiet_NaN(), 0};
    return {0.1, 0};
  }
};

}  // namespace

SALSA_BEHAVIOR(TestNan, "test_nan", "Test behavior: steers NaN from time `at` on")
