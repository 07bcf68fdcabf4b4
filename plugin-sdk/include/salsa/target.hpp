#pragma once
// Target kinds: what drones search for (trees, people, hot spots). Targets are points with a radius,
// static unless the kind moves them (people walking); they are not physics bodies.
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
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
  /// The farthest centre distance (m) at which `in_view` may be true for a camera of `camera_range` m.
  /// The core keeps targets in a grid and asks `in_view` only about those closer than this, so an
  /// `in_view` that sees farther than the default must widen this too (or it is never asked about the
  /// far targets). Keep it tight: it sets the grid's cell size and the work per drone. Finite, >= 0.
  virtual double view_range(double camera_range) const { return camera_range + radius(); }
  /// Where `count` targets go (exactly `count` points inside the bounds; throw when they cannot be
  /// placed). Default: uniform over free space (never inside obstacles); it gives up, with an error,
  /// when fewer than 1 in 1,000 random points so far had room for a target.
  virtual std::vector<Vec2> place(std::size_t count, const WorldView& world, Rng& rng) const {
    std::vector<Vec2> out;
    out.reserve(count);
    const Rect b = world.bounds();
    for (std::size_t tries = 0; out.size() < count; ++tries) {
      if (tries > 1000 * (out.size() + 10))
        throw std::runtime_error("room for only " + std::to_string(out.size()) + " of " + std::to_string(count) +
                                 " targets of radius " + Parameter::format(radius()) + " m in " + std::to_string(tries) +
                                 " random points: the map has too little free space (allowed: fewer targets, a smaller"
                                 " radius or a larger map)");
      const Vec2 p = rng.in_rect(b);
      if (world.is_free(p, radius())) out.push_back(p);
    }
    return out;
  }

  // ---- Moving targets. A kind that moves its targets says so in moves() and moves them in move();
  // the other two members are then never called.
  /// Whether the targets move: then the core calls move() once a step, after the drones moved.
  virtual bool moves() const { return false; }
  /// The fastest a target moves (m/s, finite, >= 0). The core refuses a move() that went farther in a
  /// step, and a time step in which a target would move more than its radius (it could step through
  /// a wall): at most radius() / max_speed() s.
  virtual double max_speed() const { return 0; }
  /// One step of `world.dt()` s: each target from `positions[i]` to where it is at the step's end
  /// (written over it). `velocities[i]` (m/s) is the target's own state: zero before its first step,
  /// kept between steps as move() left it (its heading when it stops, for instance). A target must stay
  /// where it is or end on a free point (`world.is_free(p, radius())`: clear of obstacles, inside the
  /// bounds); the core refuses anything else. `world` holds the map and the time but no drones, and `rng`
  /// is the targets' own stream: the targets walk the same paths whatever the drones do, so the
  /// behaviors of a repeat meet the same people in the same places. Found targets move on.
  virtual void move(std::span<Vec2> positions, std::span<Vec2> velocities, const WorldView& world, Rng& rng) const {
    (void)positions, (void)velocities, (void)world, (void)rng;
  }
};

}  // namespace salsa
