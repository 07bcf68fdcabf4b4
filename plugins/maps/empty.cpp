// An empty square closed by walls: the world of the SALSA paper's benchmark, without its spawn offset.
#include <salsa/sdk.hpp>

namespace {

class EmptyMap final : public salsa::MapGenerator {
  salsa::Param size{this, "size", 1000.0, 10.0, 1e6, "m", "side of the square"};

 public:
  salsa::MapData generate(const std::string&, salsa::Rng&) const override {
    salsa::MapData map;
    map.bounds = {{0, 0}, {size, size}};
    map.spawn = map.bounds.centre();
    return map;
  }
};

}  // namespace

SALSA_MAP(EmptyMap, "empty", "Empty square closed by walls, spawn at the centre")
