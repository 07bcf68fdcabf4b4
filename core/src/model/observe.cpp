// Observe: what observers and outputs ask of the swarm between steps.
#include "salsa/core/model/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace salsa {

std::vector<double> Simulation::nearest_neighbour_distances() const {
  const std::size_t n = drones_.positions.size();
  std::vector<double> out(n, std::numeric_limits<double>::infinity());
  if (flying_ < 2) return out;
  const bool everyone = flying_ == n;
  // Cells sized by the grid to the drones' spread (not the detection range, which may be 0 or span the
  // map); the search widens from one cell until it finds someone, and ends once it covers the map.
  PointGrid grid;
  grid.build(drones_.positions, 0);
  const Rect& b = setup_.map.bounds;
  const double far = std::hypot(b.width(), b.height());
  for (std::uint32_t i = 0; i < n; ++i)
    for (double r = grid.cell_size(); everyone || drones_.status[i] == DroneStatus::flying; r *= 4) {  // r > 0, so r >= far within a few dozen rounds
      grid.query(drones_.positions[i], r, [&](std::uint32_t j, Vec2, double d2) {
        if (j != i && (everyone || drones_.status[j] == DroneStatus::flying)) out[i] = std::min(out[i], std::sqrt(d2));
      });
      if (!std::isinf(out[i]) || r >= far) break;
    }
  return out;
}

}  // namespace salsa
