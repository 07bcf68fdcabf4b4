// my_wind: a salsa wind field. A sea breeze: the sea lies beyond y = coast and the wind blows inland
// (towards −y) at `speed` over the water, fading linearly to calm `reach` m inland. A test uses it as
// "wind": {"field": "my_wind"}, added to its constant wind and gusts.
#include <salsa/sdk.hpp>

#include <algorithm>

namespace {

class MyWind final : public salsa::WindField {
  // Each parameter once: name, default, min, max, unit, meaning; it reads as a double.
  salsa::Param speed{this, "speed", 4.0, 0.0, 30.0, "m/s", "wind speed over the sea and at the coast"};
  salsa::Param coast{this, "coast", 300.0, -1e6, 1e6, "m", "y of the coast line; the sea lies beyond it"};
  salsa::Param reach{this, "reach", 200.0, 1.0, 1e6, "m", "how far inland the breeze is felt"};

 public:
  // Called once per flying drone per step, at the drone's position: cheap, and the same for the same p and t.
  salsa::Vec2 velocity(salsa::Vec2 p, double) const override {
    const double inland = coast - p.y;  // m from the coast, > 0 over land
    const double share = std::clamp(1 - inland / reach, 0.0, 1.0);
    return {0, -speed * share};
  }
};

}  // namespace

SALSA_WIND(MyWind, "my_wind", "A sea breeze: wind that strengthens towards the coast")
