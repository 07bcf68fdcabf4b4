#pragma once
// Contact handlers: react to drones seeing targets and to collisions (e.g. mark trees found, count or
// penalise crashes). Called serially in the detect phase, in a fixed order.
#include <cstdint>

#include "salsa/parameters.hpp"
#include "salsa/vec2.hpp"

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

/// What a handler may change.
class ContactActions {
 public:
  virtual ~ContactActions() = default;
  /// Mark a target found (for good) by a drone; later calls for the same target do nothing.
  virtual void mark_found(std::uint32_t target, std::uint32_t drone) = 0;
  virtual bool is_found(std::uint32_t target) const = 0;
};

class ContactHandler : public Configurable {
 public:
  virtual void on_contact(const ContactEvent& event, ContactActions& actions) = 0;
};

}  // namespace salsa
