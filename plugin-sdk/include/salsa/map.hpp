#pragma once
// Maps: bounds, static obstacles and a spawn point, made by a map generator from its parameters (and,
// for file-based maps, a file).
#include <stdexcept>
#include <string>
#include <vector>

#include "salsa/parameters.hpp"
#include "salsa/rng.hpp"
#include "salsa/vec2.hpp"

namespace salsa {

using Polyline = std::vector<Vec2>;

struct MapData {
  Rect bounds;                     ///< m; closed by walls on all four sides
  std::vector<Polyline> obstacles; ///< solid polygons (closed; inside is blocked)
  std::vector<Polyline> hollow;    ///< closed outlines whose inside is free (rooms, courtyards)
  std::vector<Polyline> lines;     ///< open wall polylines
  Vec2 spawn;                      ///< m; where drones start
};

/// Thrown by a map generator for bad input; the message names the field and what is allowed.
struct MapError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class MapGenerator : public Configurable {
 public:
  /// `file` is the map file for file-based generators ("" when none was given).
  virtual MapData generate(const std::string& file, Rng& rng) const = 0;
};

}  // namespace salsa
