// A wind field that goes wrong from time `at` on: a failure while running, which must be reported
// naming the wind plugin and its file (exit status 1), with the data written so far kept.
#include <limits>
#include <stdexcept>

#include <salsa/sdk.hpp>

namespace {

class BadWind final : public salsa::WindField {
  salsa::Param at{this, "at", 0.5, 0.0, 1e6, "s", "time from which the field goes wrong"};
  salsa::Param mode{this, "mode", 0, 0, 2, "", "0: NaN, 1: 10 km/s, 2: throws", 1};

 public:
  salsa::Vec2 velocity(salsa::Vec2, double t) const override {
    if (t < at) return {1, 0};
    if (mode == 0) return {std::numeric_limits<double>::quiet_NaN(), 0};
    if (mode == 1) return {1e4, 0};
    throw std::runtime_error("no data for this hour");
  }
};

}  // namespace

SALSA_WIND(BadWind, "bad_wind", "Test wind: NaN, absurd or throwing from time `at` on")
