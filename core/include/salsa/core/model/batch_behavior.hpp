#pragma once
// Behaviors that decide for a whole group at once (a Python class through numpy, docs/python.md):
// the core gathers the Perceptions of the group's flying drones into flat arrays and calls the behavior
// once per step. Core-side only: the plugin SDK (and its ABI) knows nothing of it, and a BatchBehavior is
// a Behavior everywhere a Behavior goes (a factory, a group, live changes).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "salsa/behavior.hpp"

namespace salsa {

/// The Perceptions of one group's flying drones this step (after sensor noise, as a C++ behavior gets
/// them), one row per drone in id order. Per-drone lists (neighbours, targets, obstacle hits, messages)
/// are flat, row r's items at [offsets[r], offsets[r + 1]) (compressed sparse rows).
struct PerceptionBatch {
  template <class Item>
  struct Rows {
    std::vector<std::int64_t> offsets{0};  ///< size() + 1 entries
    std::vector<Item> items;
  };

  // What the group's drones share (Perception's fields of the same names).
  std::uint32_t group = 0;
  double time = 0, dt = 0;
  DroneProperties drone;  ///< max_speed, max_force, radius, mass, camera_range, obstacle_range, detection_range
  Vec2 base;
  double battery_capacity = 0;
  Senses senses;  ///< what was gathered: the lists not sensed stay empty

  // One entry per drone.
  std::vector<std::uint32_t> id;
  std::vector<Vec2> position, velocity, air_velocity, wind;
  std::vector<double> battery;

  Rows<Neighbour> neighbours;
  Rows<TargetSeen> targets;
  Rows<ObstacleHit> obstacles;
  /// The messages received; each one's payload is copied to `payloads`, at [payload_offsets[m],
  /// payload_offsets[m + 1]) for message m (its `payload` span points there).
  Rows<Message> messages;
  std::vector<double> payloads;
  std::vector<std::int64_t> payload_offsets{0};

  std::size_t size() const { return id.size(); }
  /// Empty, capacity kept.
  void clear();
  /// One more row: `me` as it is (its group's shared fields taken from it). Call finish() after the last.
  void append(const Perception& me, Senses senses);
  /// Points each message's payload span at its copy in `payloads` (which appending may move).
  void finish();
  /// `parts` (each finished) one after the other, rows and items in order; finished.
  void assign(std::span<const PerceptionBatch> parts);
};

/// The drones' own random streams, one per row of a batch: the very Rng objects a C++ behavior draws
/// from, so a batch port draws what its original draws when it draws in the same order.
class BatchRng {
 public:
  BatchRng(std::span<Rng> rngs, std::span<const std::uint32_t> ids) : rngs_(rngs), ids_(ids) {}
  std::size_t size() const { return ids_.size(); }
  Rng& operator[](std::size_t row) { return rngs_[ids_[row]]; }

 private:
  std::span<Rng> rngs_;
  std::span<const std::uint32_t> ids_;
};

/// Where a batch's drones broadcast: row r's drone's outbox this step, as its Perception holds it (null
/// where nobody receives: a batch of one made from a Perception without one).
class BatchOutbox {
 public:
  BatchOutbox(std::span<Outbox* const> outboxes, std::span<const std::uint32_t> ids) : outboxes_(outboxes), ids_(ids) {}
  std::size_t size() const { return ids_.size(); }
  /// Row r's drone broadcasts `payload` this step, as Perception::broadcast does (a second call
  /// replaces the first; longer than message_size(): std::length_error naming the drone).
  void broadcast(std::size_t row, std::span<const double> payload) const {
    Perception me;
    me.id = ids_[row], me.outbox = outboxes_[row];
    me.broadcast(payload);
  }

 private:
  std::span<Outbox* const> outboxes_;
  std::span<const std::uint32_t> ids_;
};

/// A behavior that decides for its group's flying drones in one call per step, on the stepping thread,
/// after the other groups' drones decided. `decide_batch` writes steering[r] for row r (m/s, as
/// Behavior::decide returns) and may broadcast for any row through `outbox`. The batch is shared: a
/// behavior may keep it past the call (views handed to Python do), and the core then gathers the next
/// step into fresh memory.
class BatchBehavior : public Behavior {
 public:
  virtual void decide_batch(const std::shared_ptr<const PerceptionBatch>& batch, BatchRng& rng, const BatchOutbox& outbox,
                            std::span<Vec2> steering) = 0;
  /// One drone as a batch of one (salsa::testing's Scene, a caller that decides drone by drone).
  Vec2 decide(const Perception& me, Rng& rng) final;
};

}  // namespace salsa
