// rings.cpp: a map generator. Concentric ring walls around the spawn point, each with one doorway,
// the doorways turning a quarter turn from ring to ring.
#include <cmath>

#include <salsa/sdk.hpp>

namespace {

class Rings final : public salsa::MapGenerator {
  salsa::Param rings{this, "rings", 3, 1, 20, "", "number of ring walls", 1};
  salsa::Param spacing{this, "spacing", 60.0, 10.0, 1000.0, "m", "distance between rings"};
  salsa::Param doorway{this, "doorway", 20.0, 5.0, 500.0, "m", "width of each ring's opening"};

 public:
  salsa::MapData generate(const std::string&, salsa::Rng&) const override {
    const double half = (rings + 1) * spacing;
    salsa::MapData map;
    map.bounds = {{0, 0}, {2 * half, 2 * half}};
    map.spawn = map.bounds.centre();
    for (int k = 1; k <= static_cast<int>(rings); ++k) {
      const double r = k * spacing, door = doorway / r;  // the opening as an angle
      if (door >= 2 * salsa::pi) throw salsa::MapError("rings: doorway " + salsa::Parameter::format(doorway) +
                                                       " m is wider than ring " + std::to_string(k));
      const double from = k * salsa::pi / 2 + door / 2, arc = 2 * salsa::pi - door;
      salsa::Polyline wall;
      for (int i = 0; i <= 64; ++i) wall.push_back(map.spawn + salsa::Vec2::polar(r, from + arc * i / 64));
      map.lines.push_back(wall);
    }
    return map;
  }
};

}  // namespace

SALSA_MAP(Rings, "rings", "Concentric ring walls with one doorway each")
