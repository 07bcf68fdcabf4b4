// A map plugin that hands the core bad data on request (its parameter `kind`), so the tests can check
// that plugin data is validated like a user's map file and refused naming the plugin.
#include <cmath>
#include <limits>
#include <stdexcept>

#include <salsa/sdk.hpp>

namespace {

class TestBadMap final : public salsa::MapGenerator {
 public:
  static salsa::Parameters declare() {
    return {{"kind", 0, 0, 9, "",
             "0 good; 1 NaN bounds; 2 infinite obstacle point; 3 obstacle point outside the bounds; 4 obstacle of 2 "
             "points; 5 NaN spawn; 6 line of 1 point; 7 generate() throws; 8 bounds of 1e12 m; 9 NaN hollow point",
             1}};
  }

  salsa::MapData generate(const std::string&, salsa::Rng&) const override {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    salsa::MapData map;
    map.bounds = {{0, 0}, {100, 100}};
    map.spawn = {50, 50};
    map.obstacles = {{{10, 10}, {20, 10}, {20, 20}}};
    map.lines = {{{70, 10}, {70, 40}}};
    switch (static_cast<int>(param("kind"))) {
      case 1: map.bounds.max.x = nan; break;
      case 2: map.obstacles[0][1] = {inf, 10}; break;
      case 3: map.obstacles[0][2] = {20, 120}; break;
      case 4: map.obstacles[0].pop_back(); break;
      case 5: map.spawn = {nan, 50}; break;
      case 6: map.lines[0].pop_back(); break;
      case 7: throw std::runtime_error("no terrain today");
      case 8: map.bounds = {{0, 0}, {1e12, 1e12}}; map.spawn = {5e11, 5e11}; break;
      case 9: map.hollow = {{{30, 60}, {40, 60}, {nan, 70}}}; break;
      default: break;
    }
    return map;
  }
};

}  // namespace

SALSA_MAP(TestBadMap, "test_bad_map", "Test map: returns bad data of the kind asked for")
