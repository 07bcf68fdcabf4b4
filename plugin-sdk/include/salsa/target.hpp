#pragma once
// Target kinds: what drones search for (trees, people, hot spots). Targets are static points with a
// radius; they are not physics bodies.
#include <cstddef>
#include <vector>

#include "salsa/parameters.hpp"
#include "salsa/rng.hpp"
#include "salsa/world.hpp"

namespace salsa {

class TargetKind : public Configurable {
 public:
  /// Radius of one target (m); also its clearance from obstacles when placed.
  virtual double radius() const = 0;
  /// Whether a drone whose centre is `distance` m from the target's centre sees it with a camera of
  /// `camera_range` m. Default: the target's disc overlaps the camera's disc.
  virtual bool in_view(double distance, double camera_range) const { return distance < camera_range + radius(); }
  /// Where `count` targets go. Default: uniform over free space (never inside obstacles).
  virtual std::vector<Vec2> place(std::size_t count, const WorldView& world, Rng& rng) const {
    std::vector<Vec2> out;
    out.reserve(count);
    const Rect b = world.bounds();
    for (std::size_t tries = 0; out.size() < count; ++tries) {
      const Vec2 p = rng.in_rect(b);
      if (world.is_free(p, radius()) || tries > 1000 * (count + 10)) out.push_back(p);
    }
    return out;
  }
};

}  // namespace salsa
