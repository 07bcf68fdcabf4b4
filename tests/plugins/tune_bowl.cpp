// A behavior whose outcome is a known smooth function of its parameters, for salsa tune's tests: every
// drone flies along +x at speed
//   f(a, b, c) = 8 − 0.2 (a − 6)² − 1.5 (log10 b)² − 0.02 (c − 8)²   (at least 0),
// plus normal noise of standard deviation `noise` drawn from the drone's own stream (so it depends on
// the world's seed, the same for every candidate on that world). summary.csv's mean_speed is then f
// plus the drones' mean noise: the optimum is a = 6, b = 1, c = 8, where it is 8.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <salsa/sdk.hpp>

namespace {

class TuneBowl final : public salsa::Behavior {
 public:
  salsa::Param a{this, "a", 1.0, 0.0, 10.0, "", "optimum at 6"};
  salsa::Param b{this, "b", 10.0, 0.01, 100.0, "", "optimum at 1 (a log scale by the tune's rule)"};
  salsa::Param c{this, "c", 15, 0, 20, "", "a whole number, optimum at 8", 1};
  salsa::Param noise{this, "noise", 0.2, 0.0, 5.0, "m/s", "standard deviation of each drone's speed noise"};
  salsa::Param fail_above{this, "fail_above", 10.0, 0.0, 10.0, "", "decide throws when a is above this"};

  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng& rng) override {
    if (a > fail_above) throw std::runtime_error("tune_bowl: a is above fail_above, as asked");
    const double f = 8 - 0.2 * (a - 6) * (a - 6) - 1.5 * std::log10(b) * std::log10(b) - 0.02 * (c - 8) * (c - 8);
    const double speed = std::clamp(std::max(0.0, f) + noise * rng.normal(), 0.0, me.max_speed);
    return salsa::Vec2{speed, 0} - me.velocity;
  }
};

}  // namespace

SALSA_BEHAVIOR(TuneBowl, "test_bowl", "Flies along +x at a known smooth function of a, b and c (salsa tune's tests)")
