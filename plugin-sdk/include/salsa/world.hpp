#pragma once
// What a plugin may see of the world: read-only views, no Box2D, Qt or JSON types.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "salsa/map.hpp"
#include "salsa/vec2.hpp"

namespace salsa {

/// What a drone is doing. A landed drone (its battery ran out) or a failed one stays where it stopped,
/// in every span indexed by id, but senses, decides and is seen by no one; it stays in the outputs.
enum class DroneStatus : std::uint8_t {
  flying = 0,
  landed = 1,  ///< battery empty
  failed = 2,  ///< the whole drone failed (a failure model or a timed change)
  removed = 3, ///< taken out by a lower drone count; its id is never reused and it is in no output
};

/// A drone's view of another drone within its drone-detection range.
struct Neighbour {
  Vec2 position;     ///< m
  Vec2 velocity;     ///< m/s
  double distance;   ///< m, centre to centre
  std::uint32_t id;
  std::uint32_t group = 0;  ///< index of its group in the test's "groups" (0 without groups)
};

/// Where a ray from the drone hit static geometry (walls, obstacles) within obstacle range.
struct ObstacleHit {
  Vec2 point;        ///< m
  double distance;   ///< m from the drone's centre
};

/// A target within camera range (as the target kind defines "in view"), or a false detection.
struct TargetSeen {
  /// The id of a false detection (the drone configuration's false_detection_rate): a target that is not
  /// there, never found and never handed to a contact handler. Check for it before indexing by id.
  static constexpr std::uint32_t phantom = 0xFFFFFFFF;
  Vec2 position;     ///< m
  double distance;   ///< m, centre to centre
  std::uint32_t id;  ///< the target's id, or `phantom`
  bool found;        ///< already found by any drone (false for a phantom)
};

/// The most doubles one message may hold (Behavior::message_size is refused above it).
inline constexpr std::size_t max_message_size = 64;

/// A message another drone broadcast, as this drone received it (Perception::messages): where the
/// sender was as the receiver measured it when it was sent, with the test's comm noise. Range and bearing
/// are computed when asked, so a behavior that reads only payloads pays for neither.
struct Message {
  std::uint32_t sender;   ///< the sender's drone id
  std::uint32_t group;    ///< the sender's group (index into the test's "groups"; 0 without groups)
  Vec2 offset;            ///< m: from the receiver to the sender in the map's frame (range and bearing noise added)
  double time;            ///< s: when it was sent (the start of the step it was broadcast in)
  std::span<const double> payload;  ///< what the sender broadcast; valid during the decide call it came with
  /// m from the receiver to the sender (with range noise; never below 0).
  double range() const { return offset.length(); }
  /// rad: direction from the receiver to the sender, atan2(dy, dx) in [−π, π] (with bearing noise; 0
  /// when the range is 0).
  double bearing() const { return offset.angle(); }
};

/// One drone's message slot for the current step, provided by the core. Write it only through
/// Perception::broadcast: the core checks every outbox it reads, and one whose room or size was set by
/// hand fails the test, naming the behavior.
struct Outbox {
  std::span<double> room;  ///< message_size() doubles
  std::size_t size = 0;    ///< doubles in the message
  bool sent = false;       ///< broadcast was called this step
};

/// The properties every drone of a group shares (its drone configuration).
struct DroneProperties {
  double camera_range = 0;     ///< m
  double obstacle_range = 0;   ///< m
  double detection_range = 0;  ///< m
  double max_speed = 0;        ///< m/s
  double max_force = 0;        ///< largest velocity change of one steering term per step, m/s
  double radius = 0;           ///< m
  double mass = 0;             ///< kg
};

/// Read-only query of the whole world: for a behavior's `prepare()`, a target kind's placement, a
/// contact handler (`reset`, `ContactActions::world()`) and a metric. Valid only during the call it is
/// passed to.
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
  /// The drones' shared properties, so that state sized by them (a grid of camera-range cells, a
  /// partition by detection range) can be built in `prepare()` before any drone decides. They change
  /// when the GUI changes the drone configuration live: compare, do not cache for good.
  virtual const DroneProperties& drone(std::uint32_t group = 0) const = 0;
  /// Each drone's group (index into the test's "groups"; all 0 without groups) and status, by id.
  virtual std::span<const std::uint32_t> drone_groups() const = 0;
  virtual std::span<const DroneStatus> drone_status() const = 0;
  /// How many groups the test has (1 without "groups"), and each one's base: its spawn point (m).
  virtual std::size_t group_count() const = 0;
  virtual Vec2 base(std::uint32_t group) const = 0;
  /// The map as generated (bounds, solid obstacles, hollow outlines, open lines, spawn point; m), for
  /// plugins that lay out their own structures over it (a pheromone field that skips obstacles, a
  /// route around rooms). A live map change in the GUI re-spawns the drones, which calls `reset`.
  virtual const MapData& map() const = 0;
};

/// Everything one drone knows when it decides, valid only during that `decide` call.
struct Perception {
  std::uint32_t id = 0;
  Vec2 position;           ///< m
  /// m/s over the ground, as the drone's navigation measures it (and neighbours see it). Steering
  /// changes the air velocity, so `desired − velocity` (steer_towards) makes the ground velocity
  /// `desired` when the drone can fly it: full_speed (behavior.hpp) gives the fastest it can.
  Vec2 velocity;
  /// m/s relative to the air: velocity minus the wind it flew in during the last step. What max_speed
  /// bounds and the power model draws for; equal to `velocity` in a test without wind.
  Vec2 air_velocity;
  /// m/s: the wind where the drone is, the one it flies in this step (the test's constant wind, gusts
  /// and wind field), as a drone's wind estimate gives it; zero without wind. With it the steering
  /// helpers aim for ground velocities the drone can fly: into a headwind, max speed − |wind|.
  Vec2 wind;
  double max_speed = 0;    ///< m/s, relative to the air
  double max_force = 0;    ///< largest velocity change of one steering term per step, m/s (the paper's convention)
  double radius = 0;       ///< m
  double mass = 0;         ///< kg
  double camera_range = 0;     ///< m
  double obstacle_range = 0;   ///< m
  double detection_range = 0;  ///< m
  double dt = 0;           ///< s per step
  double time = 0;         ///< s since start
  std::uint32_t group = 0;     ///< index of the drone's group (0 without groups)
  Vec2 base;                   ///< m: its group's base (spawn point), where a battery may be recharged
  double battery = 1;          ///< fraction of the battery left, 0 to 1 (1 without a battery model)
  double battery_capacity = 0; ///< Wh; 0: no battery model, the drone never runs flat
  std::span<const Neighbour> neighbours;   ///< drones within detection_range, nearest not first
  std::span<const ObstacleHit> obstacles;  ///< ray hits within obstacle_range
  std::span<const TargetSeen> targets;     ///< targets in camera view
  /// Messages received this step: what other drones broadcast in an earlier step and the test's comm
  /// model delivered (docs/plugins.md#messages-drones-that-talk), in the drone grid's order as
  /// neighbours are (nearest first when the model caps them). Empty without "comm".
  std::span<const Message> messages;
  const WorldView* world = nullptr;
  /// Where broadcast writes: the core's slot for this drone and step. Null in a Perception made by
  /// hand (salsa/testing.hpp's Scene), where broadcast does nothing.
  Outbox* outbox = nullptr;

  /// Broadcasts one message this step (a second call in the same step replaces the first). Drones in
  /// the comm model's reach receive it in a later step's `messages`; without "comm" nobody does.
  /// Throws std::length_error for a payload longer than the behavior's message_size(): the core reports
  /// that as the behavior's failure.
  void broadcast(std::span<const double> payload) const {
    if (!outbox) return;
    if (payload.size() > outbox->room.size())
      throw std::length_error("drone " + std::to_string(id) + " broadcast " + std::to_string(payload.size()) +
                              " doubles, more than the " + std::to_string(outbox->room.size()) +
                              " its behavior declares (Behavior::message_size)");
    std::copy(payload.begin(), payload.end(), outbox->room.begin());
    outbox->size = payload.size();
    outbox->sent = true;
  }
};

}  // namespace salsa
