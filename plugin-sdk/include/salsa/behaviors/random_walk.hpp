#pragma once
// Random walk: each drone flies at full speed along a random heading for a random time, then picks a
// new one. No communication. Obstacles close ahead make it turn away instead of grinding along walls.
// Derive to change how long a heading lasts or which heading comes next (docs/plugins.md).
#include <algorithm>
#include <cstdio>
#include <string>

#include "salsa/behavior.hpp"

namespace salsa::behaviors {

struct RandomWalkMemory {
  double heading = 0;    // rad
  double time_left = 0;  // s until the next heading change
  bool started = false;
};

class RandomWalk : public BehaviorWithMemory<RandomWalkMemory> {
 public:
  Vec2 decide(const Perception& me, RandomWalkMemory& w, Rng& rng) override {
    if (!w.started) {  // keep the spawn velocity's heading so the first step has no jolt
      w = {me.velocity.is_zero() ? rng.angle() : me.velocity.angle(), duration(rng), true};
    }
    w.time_left -= me.dt;
    if (w.time_left <= 0) w = {next_heading(me, w, rng), duration(rng), true};

    // Close hits: if we are heading into them, pick a new heading within ±60° of straight away.
    Vec2 away;
    for (const auto& h : me.obstacles)
      if (h.distance < turn_distance * me.obstacle_range) away += (me.position - h.point).normalized();
    if (!away.is_zero() && Vec2::polar(1, w.heading).dot(away) < 0)
      w = {away.angle() + rng.uniform(-pi / 3, pi / 3), duration(rng), true};

    return steer_towards(me, full_speed(me, w.heading)) + obstacle_weight * avoid_near_obstacles(me);
  }

  Senses senses() const override { return {.neighbours = false, .targets = false}; }  // obstacles only

  std::string inspect(std::uint32_t id) const override {
    if (id >= memory().size() || !memory()[id].started) return {};
    const RandomWalkMemory& w = memory()[id];
    char text[96];
    std::snprintf(text, sizeof text, "heading %.0f°, %.1f s until the next", w.heading * 180 / pi, w.time_left);
    return text;
  }

 protected:
  /// How long the next heading is kept (s): uniform in [min_duration, max_duration] (a max below the
  /// min means "exactly the min"). A Lévy walk draws from a heavy tail here.
  virtual double duration(Rng& rng) const {
    return rng.uniform(min_duration, std::max(min_duration.value(), max_duration.value()));
  }
  /// The heading after one ran out (rad): uniform. `w` still holds the old one.
  virtual double next_heading(const Perception& me, const RandomWalkMemory& w, Rng& rng) const {
    (void)me, (void)w;
    return rng.angle();
  }

  Param min_duration{this, "min_duration", 2.0, 0.1, 600.0, "s", "shortest time a heading is kept"};
  Param max_duration{this, "max_duration", 10.0, 0.1, 600.0, "s", "longest time a heading is kept"};
  Param turn_distance{this, "turn_distance", 0.33, 0.0, 1.0, "",
                      "obstacle hits closer than this fraction of obstacle range make the drone turn away"};
  Param obstacle_weight{this, "obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"};
};

}  // namespace salsa::behaviors
