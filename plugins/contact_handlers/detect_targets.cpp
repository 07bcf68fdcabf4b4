// The default handler for searches: a target counts as found the first time any drone sees it.
#include <salsa/sdk.hpp>

namespace {

class DetectTargets final : public salsa::ContactHandler {
 public:
  // A target seen again is already found: the first sighting is the one that counts.
  salsa::Sightings sightings() const override { return salsa::Sightings::on_entry; }
  void on_contact(const salsa::ContactEvent& event, salsa::ContactActions& actions) override {
    if (event.kind == salsa::ContactKind::target_in_view) actions.mark_found(event.other, event.drone);
  }
};

}  // namespace

SALSA_CONTACT_HANDLER(DetectTargets, "detect_targets",
                      "Marks a target found the first time a drone has it in view")
