// dwell.cpp: a target kind and its contact handler. A nest counts as found only once one drone has
// kept it in view for `dwell` seconds in a row (a camera needs time to confirm), not at first sight.
#include <cstdint>
#include <unordered_map>

#include <salsa/sdk.hpp>

namespace {

class Nest final : public salsa::TargetKind {
  salsa::Param size{this, "radius", 1.0, 0.1, 20.0, "m", "radius of a nest"};

 public:
  double radius() const override { return size; }
};

class DwellDetect final : public salsa::ContactHandler {
  salsa::Param dwell{this, "dwell", 3.0, 0.0, 600.0, "s", "time one drone must keep a nest in view"};
  struct Watch {
    double since, last;  // s: the watch began; the target was last in view
  };
  std::unordered_map<std::uint64_t, Watch> watching_;  // by (drone, target)

 public:
  void reset(const salsa::WorldView&) override { watching_.clear(); }  // ids now name other drones

  void on_contact(const salsa::ContactEvent& e, salsa::ContactActions& actions) override {
    if (e.kind != salsa::ContactKind::target_in_view || actions.is_found(e.other)) return;
    const double dt = actions.world().dt();  // the step this event covers
    const auto [it, fresh] = watching_.try_emplace(std::uint64_t{e.drone} << 32 | e.other, Watch{e.time - dt, e.time});
    if (!fresh && e.time - it->second.last > 1.5 * dt) it->second.since = e.time - dt;  // looked away: start over
    it->second.last = e.time;
    if (e.time - it->second.since >= dwell) actions.mark_found(e.other, e.drone);
  }
};

}  // namespace

SALSA_TARGET(Nest, "nest", "Small static targets")
SALSA_CONTACT_HANDLER(DwellDetect, "dwell_detect", "A target is found after one drone watched it for dwell seconds")
