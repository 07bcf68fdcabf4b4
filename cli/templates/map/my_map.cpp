// my_map: a salsa map. A square closed by walls with a grid of square pillars, none near the centre,
// where the drones start. generate() gets the test's parameters (the Param members) and an rng
// (unused here: the same parameters always give the same map); bad parameters throw salsa::MapError
// with one line.
#include <cmath>
#include <string>

#include <salsa/sdk.hpp>

namespace {

class MyMap final : public salsa::MapGenerator {
  // Each parameter once: name, default, min, max, unit, meaning; it reads as a double.
  salsa::Param size{this, "size", 300.0, 20.0, 1e5, "m", "side of the square"};
  salsa::Param spacing{this, "spacing", 50.0, 5.0, 1e4, "m", "distance between pillar centres"};
  salsa::Param pillar{this, "pillar", 8.0, 0.5, 1e3, "m", "side of a pillar"};
  salsa::Param clear{this, "clear", 40.0, 0.0, 1e4, "m", "no pillar within this distance of the centre"};

 public:
  salsa::MapData generate(const std::string& /*file*/, salsa::Rng& /*rng*/) const override {
    const double half = pillar / 2;
    if (pillar >= spacing) throw salsa::MapError("pillar: must be smaller than spacing (" + salsa::Parameter::format(spacing) + " m)");
    if (std::pow(size / spacing, 2) > 1e6) throw salsa::MapError("spacing: more than 1,000,000 pillars (allowed: a larger spacing)");
    salsa::MapData map;
    map.bounds = {{0, 0}, {size, size}};
    map.spawn = map.bounds.centre();
    for (double x = spacing; x + half < size; x += spacing)
      for (double y = spacing; y + half < size; y += spacing)
        if (salsa::distance({x, y}, map.spawn) > clear + half * std::sqrt(2.0))
          map.obstacles.push_back({{x - half, y - half}, {x + half, y - half}, {x + half, y + half}, {x - half, y + half}});  // CCW
    return map;
  }
};

}  // namespace

SALSA_MAP(MyMap, "my_map", "Square with a grid of pillars, clear around the centre")
