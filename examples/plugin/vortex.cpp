// vortex.cpp: a wind field, a Rankine vortex (a whirlwind, the eddy behind a building): the air turns
// counter-clockwise around a centre, its speed growing linearly with the distance inside the core and
// falling off as core / distance outside it. "wind": {"field": {"name": "vortex", "params": {...}}}
#include <salsa/sdk.hpp>

#include <cmath>

namespace {

class Vortex final : public salsa::WindField {
  salsa::Param centre_x{this, "centre_x", 500.0, -1e6, 1e6, "m", "x of the vortex's centre"};
  salsa::Param centre_y{this, "centre_y", 500.0, -1e6, 1e6, "m", "y of the vortex's centre"};
  salsa::Param core{this, "core", 50.0, 0.1, 1e5, "m", "radius of the core, where the wind is strongest"};
  salsa::Param speed{this, "speed", 5.0, 0.0, 100.0, "m/s", "wind speed at the core's edge"};
  salsa::Param clockwise{this, "clockwise", 0.0, 0.0, 1.0, "", "1: turn clockwise, 0: counter-clockwise", 1.0};

 public:
  salsa::Vec2 velocity(salsa::Vec2 p, double) const override {
    const salsa::Vec2 from = p - salsa::Vec2{centre_x, centre_y};
    const double r = from.length();
    if (r == 0) return {};
    const double v = speed * (r < core ? r / core : core / r);
    const salsa::Vec2 across{-from.y / r, from.x / r};  // unit vector, a quarter turn counter-clockwise
    return across * (clockwise > 0.5 ? -v : v);
  }
};

}  // namespace

SALSA_WIND(Vortex, "vortex", "A Rankine vortex: air turning around a centre")
