// my_contact_handler: a salsa contact handler. A target counts as found only once `confirmations` different
// drones have had it in view (one drone's sighting may be a false detection). It replaces salsa's
// detect_targets (found at first sight) in a test that lists it: "contact_handlers": ["my_contact_handler"].
// Handlers are called serially, in the order the test lists them, with every event of a step.
#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class MyContactHandler final : public salsa::ContactHandler {
  // Name, default, min, max, unit, meaning, step (1: a whole number); it reads as a double.
  salsa::Param confirmations{this, "confirmations", 2, 1, 100, "", "different drones that must see a target before it counts as found", 1};

 public:
  void on_contact(const salsa::ContactEvent& event, salsa::ContactActions& actions) override {
    if (event.kind != salsa::ContactKind::target_in_view || actions.is_found(event.other)) return;
    std::vector<std::uint32_t>& drones = seen_by_[event.other];
    if (std::find(drones.begin(), drones.end(), event.drone) == drones.end()) drones.push_back(event.drone);
    if (static_cast<double>(drones.size()) >= confirmations) actions.mark_found(event.other, event.drone);
  }

 private:
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> seen_by_;  // target id -> drones that saw it
};

}  // namespace

SALSA_CONTACT_HANDLER(MyContactHandler, "my_contact_handler", "A target is found once several drones have seen it")
