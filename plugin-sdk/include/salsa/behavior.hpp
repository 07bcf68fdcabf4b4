#pragma once
// Behaviors: how a drone decides. `prepare` runs once per step, serially; `decide` runs once per drone
// and may run in parallel, so it may only write that drone's own memory.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "salsa/parameters.hpp"
#include "salsa/rng.hpp"
#include "salsa/world.hpp"

namespace salsa {

/// What a behavior reads of its Perception. The core gathers only these; the others stay empty spans
/// (the drone's own fields and its obstacle hits are always there). Declaring less is only a saving:
/// a behavior that reads a list it did not declare finds it empty.
struct Senses {
  bool neighbours = true;  ///< Perception::neighbours
  bool targets = true;     ///< Perception::targets
};

/// What a behavior's drones know beyond their own senses (Behavior::shared_state): whether a
/// comparison of its results with a radio's is fair. A queue that sets a `global` behavior beside tests
/// with a radio ("comm") says so in its warnings, its queue.json and its comparison plots.
enum class SharedState : std::uint8_t {
  none,    ///< each drone decides from its own Perception and memory alone
  global,  ///< state built in `prepare` from every drone at once (a field, a partition): knowledge no radio carried
  radio,   ///< what drones share reaches them only as the comm model's messages (Perception::messages)
};
/// "none", "global", "radio".
inline const char* to_string(SharedState s) {
  return s == SharedState::global ? "global" : s == SharedState::radio ? "radio" : "none";
}

class Behavior : public Configurable {
 public:
  /// Shared state (a pheromone field, partitions) is updated here, once per step before any `decide`.
  virtual void prepare(const WorldView&) {}
  /// Desired steering for one drone: a velocity change for this step (m/s). The core adds it to the
  /// velocity as it is and clamps the speed to max speed. Max force bounds each steering term (the
  /// helpers below clamp to it); a weighted sum of terms may exceed it, as the paper's flocking does.
  virtual Vec2 decide(const Perception& me, Rng& rng) = 0;
  /// Drones were (re)spawned: `drones` drones with ids 0..drones-1 and fresh memory. With groups, ids
  /// run over all groups; this behavior decides for the drones of its group() only.
  virtual void reset(std::size_t drones) { (void)drones; }
  /// The drone count changed while the others fly on: drones were added (ids from the old count up,
  /// fresh memory) or the highest ids removed; every other drone keeps its memory. The default calls
  /// reset (all memory fresh), for a behavior that cannot keep it.
  virtual void resize(std::size_t drones) { reset(drones); }
  /// What `decide` reads (default: everything). Asked once per step, after `prepare`.
  virtual Senses senses() const { return {}; }
  /// A few lines about drone `id`'s memory for the GUI's inspector ("" = nothing to show). Called
  /// between steps, on the stepping thread.
  virtual std::string inspect(std::uint32_t id) const { (void)id; return {}; }
  /// The most doubles one message of this behavior holds (Perception::broadcast); 0 (the default): its
  /// drones never broadcast. Asked when the behavior starts; more than max_message_size is refused.
  virtual std::size_t message_size() const { return 0; }
  /// What its drones share (default: none). Asked after the parameters are set, so it may depend on
  /// them (a `sharing` parameter). Declare `global` for state `prepare` builds from all drones' data
  /// that decide then reads; `radio` when that knowledge travels only in messages.
  virtual SharedState shared_state() const { return SharedState::none; }

  /// The group this behavior decides for (index into WorldView::drone_groups()); 0 without groups.
  /// Shared state built in `prepare` should count only its group's flying drones.
  std::uint32_t group() const { return group_; }

 private:
  friend class Simulation;
  std::uint32_t group_ = 0;
};

/// True for drone `id` when it flies and belongs to `behavior`'s group: the drones whose shared state
/// a behavior's `prepare` keeps.
inline bool is_member(const WorldView& world, const Behavior& behavior, std::uint32_t id) {
  return world.drone_status()[id] == DroneStatus::flying && world.drone_groups()[id] == behavior.group();
}

/// A behavior with per-drone memory `Memory`, one slot per drone, owned and sized by the core through
/// `reset`; `decide` gets the slot of the drone it decides for.
template <class Memory>
class BehaviorWithMemory : public Behavior {
 public:
  virtual Vec2 decide(const Perception& me, Memory& memory, Rng& rng) = 0;
  Vec2 decide(const Perception& me, Rng& rng) final { return decide(me, memory_[me.id], rng); }
  void reset(std::size_t drones) override { memory_.assign(drones, Memory{}); }
  void resize(std::size_t drones) override { memory_.resize(drones); }

 protected:
  const std::vector<Memory>& memory() const { return memory_; }

 private:
  std::vector<Memory> memory_;
};

// ---- Steering helpers (Reynolds' steering, as the SALSA paper's Behavior class offers) ----
// Each returns one steering term of length at most max force: clamp(desired − velocity, max force).
// A behavior weights and sums them; the core does not clamp the sum.

/// The fastest ground speed (m/s) along the unit vector `d` that the drone can fly in the wind w where
/// it is: the largest g ≥ 0 with |g·d − w| ≤ max speed (its air speed), g = d·w + √(max² − (d × w)²);
/// max speed − |w| straight into the wind, max speed + |w| straight down it. 0 when the wind is too
/// strong to make way along d: the drone then flies into it, drifting as little as it can.
inline double ground_speed_along(const Perception& me, Vec2 d) {
  const double across = d.cross(me.wind), room = me.max_speed * me.max_speed - across * across;
  return room > 0 ? std::max(0.0, d.dot(me.wind) + std::sqrt(room)) : 0.0;
}
/// The ground velocity (m/s) at full speed along `direction` (any length; zero for a zero direction):
/// max speed without wind. In wind, the fastest the drone can hold that course (ground_speed_along):
/// asking for max speed over the ground instead would bend the course downwind, and a behavior that
/// follows its own velocity (pheromone avoidance, flocking's alignment) would drift downwind for good.
inline Vec2 full_speed(const Perception& me, Vec2 direction) {
  if (me.wind.is_zero()) return direction.with_length(me.max_speed);
  const Vec2 d = direction.normalized();
  return d * ground_speed_along(me, d);
}
/// The same along a heading (rad): Vec2::polar(max_speed, heading) without wind.
inline Vec2 full_speed(const Perception& me, double heading) {
  if (me.wind.is_zero()) return Vec2::polar(me.max_speed, heading);
  const Vec2 d = Vec2::polar(1, heading);
  return d * ground_speed_along(me, d);
}

/// Steering that turns the velocity towards `desired` (m/s over the ground), at most max force.
inline Vec2 steer_towards(const Perception& me, Vec2 desired) {
  return (desired - me.velocity).clamped(me.max_force);
}
/// Full speed towards a point.
inline Vec2 seek(const Perception& me, Vec2 point) {
  return steer_towards(me, full_speed(me, point - me.position));
}
/// Full speed along `direction` (any length); zero when the direction is zero.
inline Vec2 steer_along(const Perception& me, Vec2 direction) {
  return direction.is_zero() ? Vec2{} : steer_towards(me, full_speed(me, direction));
}
/// Match the neighbours' mean velocity.
inline Vec2 alignment(const Perception& me) {
  Vec2 sum;
  for (const auto& n : me.neighbours) sum += n.velocity;
  return steer_along(me, sum);
}
/// Fly towards the neighbours' centre.
inline Vec2 cohesion(const Perception& me) {
  if (me.neighbours.empty()) return {};
  Vec2 sum;
  for (const auto& n : me.neighbours) sum += n.position;
  return steer_along(me, sum / static_cast<double>(me.neighbours.size()) - me.position);
}
/// Fly away from neighbours closer than `distance` m, weighting each by 1/d (unit(p - q) / d, written
/// as (p - q) / d² since d is known).
inline Vec2 avoid_drones(const Perception& me, double distance) {
  Vec2 sum;
  for (const auto& n : me.neighbours)
    if (n.distance > 0 && n.distance < distance) sum += (me.position - n.position) / (n.distance * n.distance);
  return steer_along(me, sum);
}
/// The three boid terms in one pass over the neighbours: the same values as alignment(me),
/// cohesion(me) and avoid_drones(me, separation_distance).
struct BoidTerms {
  Vec2 alignment, cohesion, separation;
};
inline BoidTerms boid_terms(const Perception& me, double separation_distance) {
  Vec2 velocities, positions, away;
  for (const auto& n : me.neighbours) {
    velocities += n.velocity;
    positions += n.position;
    if (n.distance > 0 && n.distance < separation_distance) away += (me.position - n.position) / (n.distance * n.distance);
  }
  if (me.neighbours.empty()) return {};
  return {steer_along(me, velocities),
          steer_along(me, positions / static_cast<double>(me.neighbours.size()) - me.position), steer_along(me, away)};
}

/// Fly away from the obstacle points the rays hit, weighting each by 1/d.
inline Vec2 avoid_obstacles(const Perception& me) {
  Vec2 sum;
  for (const auto& h : me.obstacles)
    if (h.distance > 0) sum += (me.position - h.point) / (h.distance * h.distance);
  return steer_along(me, sum);
}

/// avoid_obstacles(me) faded in as the nearest hit gets closer: zero beyond `fade` × obstacle range,
/// full at the obstacle (squared, so gentle at first). Walls that are merely in range (in a room
/// narrower than twice the range there always are some) then do not drown the drone's own steering.
inline Vec2 avoid_near_obstacles(const Perception& me, double fade = 0.5) {
  double nearest = me.obstacle_range;
  for (const auto& h : me.obstacles) nearest = std::min(nearest, h.distance);
  const double reach = fade * me.obstacle_range;
  const double closeness = reach > 0 ? std::max(0.0, 1 - nearest / reach) : 0;
  return closeness * closeness * avoid_obstacles(me);
}

}  // namespace salsa
