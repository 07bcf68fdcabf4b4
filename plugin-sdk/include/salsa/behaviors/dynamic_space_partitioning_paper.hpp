#pragma once
// Dynamic space partitioning as the SALSA paper defines it: one virtual point per drone, spread by
// mutual repulsion (partition_points.hpp, shared with salsa's version), and each drone random-walks
// within a disc around its point. Only the group's flying drones count.
//
// The disc has radius r = disc_fraction · s, s = √(area / drones) the equilibrium spacing. Outside its
// disc (at the start, or when the point moved away) a drone flies to its point. Inside, it keeps a
// heading for 0.5–1.5 × turn_interval, then draws a new one uniformly; it turns back before it would
// leave the disc: when the point it reaches if it turns now (it turns at max force, so about |v|² / a
// ahead, a = max force / dt) lies outside, it heads back in, within ±60° of the direction to its point.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "salsa/behavior.hpp"
#include "salsa/behaviors/partition_points.hpp"

namespace salsa::behaviors {

struct DiscWalk {
  double heading = 0;    // rad
  double time_left = 0;  // s until the next heading change (0: draw one)
};

class DynamicSpacePartitioningPaper : public BehaviorWithMemory<DiscWalk> {
 public:
  void reset(std::size_t drones) override {
    BehaviorWithMemory::reset(drones);
    points_.clear();  // re-seeded at the drones' positions by the next prepare
  }

  void prepare(const WorldView& world) override {
    points_.gather(world, *this);
    radius_ = disc_fraction * points_.spacing();
    // The disc stays inside the bounds; a point keeps clear of obstacles, so its drone can reach it.
    points_.spread(world, world.bounds(), point_speed, cutoff, radius_, kClearance);
  }

  Vec2 decide(const Perception& me, DiscWalk& w, Rng& rng) override {
    Vec2 steer;
    if (points_.is_member(me.id)) {
      const Vec2 point = points_[me.id], out = me.position - point;
      if (out.length_squared() > radius_ * radius_) {
        steer = seek(me, point);
        w.time_left = 0;  // a fresh heading once inside
      } else {
        if ((w.time_left -= me.dt) <= 0) w = {rng.angle(), duration(rng)};
        // Where the drone would get to if it started turning now: its turn radius, and a step, ahead.
        const double speed = me.velocity.length();
        const double reach = speed * speed * me.dt / me.max_force + speed * me.dt;
        const Vec2 ahead = me.position + me.velocity.with_length(reach);
        if (distance_squared(ahead, point) > radius_ * radius_ && Vec2::polar(1, w.heading).dot(out) > 0)
          w = {(point - me.position).angle() + rng.uniform(-pi / 3, pi / 3), duration(rng)};
        steer = steer_towards(me, full_speed(me, w.heading));
      }
    }
    return steer + obstacle_weight * avoid_near_obstacles(me);
  }

  Senses senses() const override { return {.neighbours = false, .targets = false}; }  // obstacles only

  std::string inspect(std::uint32_t id) const override {
    if (!points_.is_member(id)) return {};
    char text[128];
    std::snprintf(text, sizeof text, "point (%.0f, %.0f), disc radius %.0f m", points_[id].x, points_[id].y, radius_);
    return text;
  }

  /// The virtual points, one per drone id (m), and the discs' radius (m), as of the last prepare.
  const PartitionPoints& points() const { return points_; }
  double disc_radius() const { return radius_; }

 protected:
  /// How long a heading is kept inside the disc (s).
  virtual double duration(Rng& rng) const { return rng.uniform(0.5, 1.5) * turn_interval; }

  Param point_speed{this, "point_speed", 8.0, 0.1, 100.0, "m/s", "top speed of the virtual points while they spread"};
  Param cutoff{this, "cutoff", 1.5, 0.5, 3.0, "", "points repel within this multiple of the equilibrium spacing"};
  Param disc_fraction{this, "disc_fraction", 0.3, 0.01, 1.0, "",
                      "radius of the disc a drone walks in, as a fraction of the equilibrium spacing √(area / drones)"};
  Param turn_interval{this, "turn_interval", 3.0, 0.1, 60.0, "s", "mean time a heading is kept within the disc"};
  Param obstacle_weight{this, "obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"};

 private:
  static constexpr double kClearance = 3;  // m kept between a point and obstacles: a drone fits there

  PartitionPoints points_;
  double radius_ = 0;
};

}  // namespace salsa::behaviors
