#pragma once
// What a plugin may see of the world: read-only views, no Box2D, Qt or JSON types.
#include <cstdint>
#include <optional>
#include <span>

#include "salsa/vec2.hpp"

namespace salsa {

/// A drone's view of another drone within its drone-detection range.
struct Neighbour {
  Vec2 position;     ///< m
  Vec2 velocity;     ///< m/s
  double distance;   ///< m, centre to centre
  std::uint32_t id;
};

/// Where a ray from the drone hit static geometry (walls, obstacles) within obstacle range.
struct ObstacleHit {
  Vec2 point;        ///< m
  double distance;   ///< m from the drone's centre
};

/// A target within camera range (as the target kind defines "in view").
struct TargetSeen {
  Vec2 position;     ///< m
  double distance;   ///< m, centre to centre
  std::uint32_t id;
  bool found;        ///< already found by any drone
};

/// Read-only query of the whole world, for `prepare()` and for target placement.
class WorldView {
 public:
  virtual ~WorldView() = default;
  virtual Rect bounds() const = 0;
  virtual double time() const = 0;  ///< s since start
  virtual double dt() const = 0;    ///< s per step
  virtual std::span<const Vec2> drone_positions() const = 0;   ///< m, indexed by drone id
  virtual std::span<const Vec2> drone_velocities() const = 0;  ///< m/s, indexed by drone id
  /// True when a disc of `clearance` m around `p` is inside the bounds and touches no obstacle.
  virtual bool is_free(Vec2 p, double clearance) const = 0;
  /// First hit of static geometry on the segment from `from` to `to`, if any.
  virtual std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const = 0;
};

/// Everything one drone knows when it decides, valid only during that `decide` call.
struct Perception {
  std::uint32_t id = 0;
  Vec2 position;           ///< m
  Vec2 velocity;           ///< m/s
  double max_speed = 0;    ///< m/s
  double max_force = 0;    ///< largest velocity change of one steering term per step, m/s (the paper's convention)
  double radius = 0;       ///< m
  double mass = 0;         ///< kg
  double camera_range = 0;     ///< m
  double obstacle_range = 0;   ///< m
  double detection_range = 0;  ///< m
  double dt = 0;           ///< s per step
  double time = 0;         ///< s since start
  std::span<const Neighbour> neighbours;   ///< drones within detection_range, nearest not first
  std::span<const ObstacleHit> obstacles;  ///< ray hits within obstacle_range
  std::span<const TargetSeen> targets;     ///< targets in camera view
  const WorldView* world = nullptr;
};

}  // namespace salsa
