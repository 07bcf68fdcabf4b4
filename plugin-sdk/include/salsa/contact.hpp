#pragma once
// Contact handlers: react to drones seeing targets and to collisions (e.g. mark trees found, count or
// penalise crashes). Called serially in the detect phase, in a fixed order. A handler's parameters come
// from the test file: "contact_handlers": [{"name": "dwell_detect", "params": {"dwell": 2}}].
#include <cstdint>

#include "salsa/parameters.hpp"
#include "salsa/vec2.hpp"
#include "salsa/world.hpp"

namespace salsa {

enum class ContactKind : std::uint8_t {
  target_in_view,  ///< drone `drone` has target `other` in camera view this step
  drone_drone,     ///< drones `drone` and `other` started touching
  drone_obstacle,  ///< drone `drone` started touching a wall or obstacle (`other` unused)
};

struct ContactEvent {
  ContactKind kind;
  std::uint32_t drone;
  std::uint32_t other;
  Vec2 position;  ///< m: the target's or the contact's position
  double time;    ///< s: when the step the event happened in ends (what was in view at its start counts then)
};

/// What a handler may change, and what it may read of the world.
class ContactActions {
 public:
  virtual ~ContactActions() = default;
  /// Mark a target found (for good) by a drone; later calls for the same target do nothing. Both ids
  /// must exist (as given by events or the world): any other stops the test with an error naming the
  /// handler.
  virtual void mark_found(std::uint32_t target, std::uint32_t drone) = 0;
  virtual bool is_found(std::uint32_t target) const = 0;
  /// The world as the event saw it, so a handler can weigh an event by time (dwell, rates: `dt()` is
  /// the step the event covers, which the GUI's larger time step may change mid-run) or by the drones'
  /// state and properties. `time()` is the event's time (`ContactEvent::time`); the drones are where
  /// they were when the event was detected (for `target_in_view`, the start of the step). Valid only
  /// during `on_contact`.
  virtual const WorldView& world() const = 0;
};

/// Which `target_in_view` events a handler hears of.
enum class Sightings : std::uint8_t {
  every_step,  ///< every step a drone has a target in view (the default)
  /// only the step a target comes into a drone's view: in view now, not the step before (missed by a
  /// noisy camera counts as not in view; after drones or targets are re-made, everything comes anew).
  /// Enough for a handler whose answer to a repeated sighting is the same as to the first, such as
  /// marking found; a drone keeps a tree in view for hundreds of steps, so this skips most calls.
  on_entry,
};

class ContactHandler : public Configurable {
 public:
  /// Asked every step before the sightings are handed out. Default: every step.
  virtual Sightings sightings() const { return Sightings::every_step; }
  /// The test starts, or the simulation re-spawned its drones or re-placed its targets (in the GUI: a
  /// new drone count, map or target set): drop any per-drone or per-target state, since ids now name
  /// other drones and targets. `world` is the world from then on (its `time()` need not be 0). Called
  /// before the first `on_contact` that follows, on the stepping thread. Default: nothing.
  virtual void reset(const WorldView& world) { (void)world; }
  virtual void on_contact(const ContactEvent& event, ContactActions& actions) = 0;
};

}  // namespace salsa
