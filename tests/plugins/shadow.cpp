// Registers a map named "forest" (a built-in has that name) and one of its own. Found before the
// built-ins (a --plugin-dir folder), its "forest" wins and the built-in "forest" alone is refused:
// the built-in "empty" and "json" maps of the same library must stay.
#include <salsa/sdk.hpp>

namespace {
class Square final : public salsa::MapGenerator {
 public:
  static salsa::Parameters declare() { return {{"size", 50.0, 10.0, 1000.0, "m", "side of the square"}}; }
  salsa::MapData generate(const std::string&, salsa::Rng&) const override {
    salsa::MapData map;
    map.bounds = {{0, 0}, {param("size"), param("size")}};
    map.spawn = map.bounds.centre();
    return map;
  }
};
}  // namespace

SALSA_MAP(Square, "forest", "A square named forest, shadowing the built-in")
SALSA_MAP(Square, "test_shadow_only", "Only in the shadowing plugin")
