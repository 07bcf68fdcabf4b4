// Detect: sightings and contacts handed to the contact handlers, serially and in a fixed order.
#include "salsa/core/model/simulation.hpp"

#include <string>
#include <tuple>

#include "model/physics.hpp"
#include "model/plugin_call.hpp"
#include "model/world_views.hpp"

namespace salsa {

using namespace detail;

namespace {

class Actions final : public ContactActions {
 public:
  Actions(std::vector<TargetState>& targets, std::size_t& found, std::size_t drones, const WorldView& world, double time)
      : targets_(targets), found_(found), drones_(drones), world_(world, time), time_(time) {}
  /// The handler about to be called: ids it gives are checked here, where the fault can be named.
  std::size_t handler = 0;
  void mark_found(std::uint32_t target, std::uint32_t drone) override {
    if (target >= targets_.size()) refuse("target", target, targets_.size());
    if (drone >= drones_) refuse("drone", drone, drones_);
    if (targets_[target].found()) return;
    targets_[target].found_by = drone;
    targets_[target].found_time = time_;
    targets_[target].found_position = targets_[target].position;
    ++found_;
  }
  bool is_found(std::uint32_t target) const override { return target < targets_.size() && targets_[target].found(); }
  const WorldView& world() const override { return world_; }

 private:
  [[noreturn]] void refuse(const char* what, std::uint32_t id, std::size_t count) const {
    const std::string field = "contact_handlers[" + std::to_string(handler) + "]";
    throw PluginFailure("contact handler", handler,
                        field + ": mark_found was given " + what + " " + std::to_string(id) + ", which does not exist (allowed: " +
                            (count == 0 ? std::string("none, there are no ") + what + "s"
                                        : std::string(what) + " ids 0 to " + std::to_string(count - 1)) + ")");
  }
  std::vector<TargetState>& targets_;
  std::size_t& found_;
  std::size_t drones_;
  EventView world_;
  double time_;
};

}  // namespace

// Detect: events to the contact handlers, serially and in a fixed order: first the targets each drone
// had in view when it sensed (by drone; only those that came into view for a handler that asks for
// Sightings::on_entry), then the contacts the physics began in its step (in its order). Every event of
// a step carries the time the step ends, the time of the first row that can count it: what was in view
// on the snapshot at t is found at t + dt, so a row never misses a found target.
void Simulation::dispatch_sightings() {
  for (const Sensed& d : sensed_) {
    // Targets lie scattered in memory: ask for a drone's all at once rather than miss on each in turn.
    for (const TargetSeen& t : d.seen) __builtin_prefetch(&targets_.states[t.id], 1);
    for (const TargetSeen& t : d.seen) ++targets_.states[t.id].observations;
  }
  const auto& handlers = setup_.contact_handlers;
  if (handlers.empty()) return;
  std::vector<char> every(handlers.size());
  bool any_every = false;
  for (std::size_t k = 0; k < handlers.size(); ++k) {
    every[k] = plugin_call(handler_kind, k, [&] { return handlers[k]->sightings(); }) != Sightings::on_entry;
    any_every = any_every || every[k];
  }
  const double step_end = time_at(steps_ + 1);  // time() once this step is counted
  Actions actions(targets_.states, targets_.found, drones_.positions.size(), *this, step_end);
  auto hand_out = [&](std::uint32_t i, const TargetSeen& t, bool entered) {
    const ContactEvent e{ContactKind::target_in_view, i, t.id, t.position, step_end};
    for (std::size_t k = 0; k < handlers.size(); ++k)
      if (entered || every[k]) plugin_call(handler_kind, k, [&] { actions.handler = k, handlers[k]->on_contact(e, actions); });
  };
  for (std::uint32_t i = 0; i < sensed_.size(); ++i) {
    const auto& [seen, entered] = std::tie(sensed_[i].seen, sensed_[i].entered);
    if (!any_every) {
      for (std::uint32_t k : entered) hand_out(i, seen[k], true);
      continue;
    }
    auto next = entered.begin();
    for (std::uint32_t k = 0; k < seen.size(); ++k) {
      const bool in = next != entered.end() && *next == k;
      next += in;
      hand_out(i, seen[k], in);
    }
  }
}

void Simulation::dispatch_contacts() {
  Actions actions(targets_.states, targets_.found, drones_.positions.size(), *this, time());
  for (ContactEvent e : physics_->begun()) {
    e.time = time();
    ++collisions_;
    for (std::size_t k = 0; k < setup_.contact_handlers.size(); ++k)
      plugin_call(handler_kind, k, [&] { actions.handler = k, setup_.contact_handlers[k]->on_contact(e, actions); });
  }
}

}  // namespace salsa
