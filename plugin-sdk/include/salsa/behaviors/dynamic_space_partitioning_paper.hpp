#pragma once
// Dynamic space partitioning as the SALSA paper defines it: one virtual point per drone, spread by
// mutual repulsion (partition_points.hpp, shared with salsa's version), and each drone random-walks
// within a disc around its point. Only the group's flying drones count.
// `sharing` 0 (global): one set of points for the group. `sharing` 1 (radio): each drone broadcasts its
// point every step and moves it away from the points it heard lately (HeardPoints); its disc's radius
// comes from the spacing of the points it knows. With no radio its point stays where it started.
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
#include <vector>

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
    views_.clear();
  }

  void prepare(const WorldView& world) override {
    points_.gather(world, *this);
    if (by_radio()) return prepare_views(world);
    radius_ = disc_fraction * points_.spacing();
    // The disc stays inside the bounds; a point keeps clear of obstacles, so its drone can reach it.
    points_.spread(world, world.bounds(), point_speed, cutoff, radius_, kClearance);
  }

  Vec2 decide(const Perception& me, DiscWalk& w, Rng& rng) override {
    Vec2 steer;
    if (points_.is_member(me.id)) {
      if (by_radio()) hear(me);  // only this drone's view is written: decide may run in parallel
      const double radius = radius_of(me.id);
      const Vec2 point = point_of(me.id), out = me.position - point;
      if (out.length_squared() > radius * radius) {
        steer = seek(me, point);
        w.time_left = 0;  // a fresh heading once inside
      } else {
        if ((w.time_left -= me.dt) <= 0) w = {rng.angle(), duration(rng)};
        // Where the drone would get to if it started turning now: its turn radius, and a step, ahead.
        const double speed = me.velocity.length();
        const double reach = speed * speed * me.dt / me.max_force + speed * me.dt;
        const Vec2 ahead = me.position + me.velocity.with_length(reach);
        if (distance_squared(ahead, point) > radius * radius && Vec2::polar(1, w.heading).dot(out) > 0)
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
    if (by_radio() && (id >= views_.size() || !views_[id].seeded())) return {};
    std::snprintf(text, sizeof text, "point (%.0f, %.0f), disc radius %.0f m", point_of(id).x, point_of(id).y, radius_of(id));
    return text;
  }

  /// The virtual points, one per drone id (m), and the discs' radius (m), as of the last prepare
  /// (sharing 0).
  const PartitionPoints& points() const { return points_; }
  double disc_radius() const { return radius_; }
  /// Drone `id`'s view of the points with `sharing` 1 (empty before its first step).
  const HeardPoints& heard_points(std::uint32_t id) const { return views_.at(id); }

  SharedState shared_state() const override { return by_radio() ? SharedState::radio : SharedState::global; }
  std::size_t message_size() const override { return 2; }  // its point x, y (sharing 1)

 protected:
  /// How long a heading is kept inside the disc (s).
  virtual double duration(Rng& rng) const { return rng.uniform(0.5, 1.5) * turn_interval; }

  Param point_speed{this, "point_speed", 8.0, 0.1, 100.0, "m/s", "top speed of the virtual points while they spread"};
  Param cutoff{this, "cutoff", 1.5, 0.5, 3.0, "", "points repel within this multiple of the equilibrium spacing"};
  Param disc_fraction{this, "disc_fraction", 0.3, 0.01, 1.0, "",
                      "radius of the disc a drone walks in, as a fraction of the equilibrium spacing √(area / drones)"};
  Param turn_interval{this, "turn_interval", 3.0, 0.1, 60.0, "s", "mean time a heading is kept within the disc"};
  Param obstacle_weight{this, "obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"};
  Param sharing{this, "sharing", 0, 0, 1, "",
                "0: one set of points for the group (global, the paper's); 1: each drone's own view, from the points its radio heard", 1};
  Param forget_after{this, "forget_after", 60.0, 0.1, 600.0, "s", "with sharing 1: a point not heard for this long is dropped from a drone's view"};

  bool by_radio() const { return sharing.value() == 1; }

 private:
  static constexpr double kClearance = 3;  // m kept between a point and obstacles: a drone fits there

  Vec2 point_of(std::uint32_t id) const { return by_radio() ? views_[id].own() : points_[id]; }
  double radius_of(std::uint32_t id) const { return by_radio() ? disc_fraction * views_[id].spacing() : radius_; }

  // Sharing 1, once a step: each member's own point moves away from the points it knows.
  void prepare_views(const WorldView& world) {
    const auto drones = world.drone_positions();
    if (views_.size() < drones.size()) views_.resize(drones.size());
    for (std::uint32_t i : points_.members()) {
      HeardPoints& v = views_[i];
      if (!v.seeded()) v.seed(drones[i]);
      v.refresh(i, world.time(), forget_after, world.bounds().area());
      v.spread(i, world, world.bounds(), point_speed, cutoff, disc_fraction * v.spacing(), kClearance);
    }
  }

  // Sharing 1, in decide: the points heard, into this drone's view; then its own broadcast.
  void hear(const Perception& me) {
    HeardPoints& v = views_[me.id];
    for (const Message& m : me.messages)
      if (m.group == group() && m.payload.size() == 2) v.hear(m.sender, {m.payload[0], m.payload[1]}, m.time);
    const double message[2] = {v.own().x, v.own().y};
    me.broadcast(message);
  }

  PartitionPoints points_;
  double radius_ = 0;
  std::vector<HeardPoints> views_;  // by drone id (sharing 1)
};

}  // namespace salsa::behaviors
