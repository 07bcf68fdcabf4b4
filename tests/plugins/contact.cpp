// A contact handler built by the test suite as a plugin author writes one: a target counts as found once
// it has been in some drone's view for `dwell` seconds in all (each step counted once, whoever saw it).
// It needs its parameter, dt from reset, and the event's world; it throws when the core hands it
// something inconsistent (an event before reset, a world whose time is not the event's).
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <salsa/sdk.hpp>

namespace {

class TestDwell final : public salsa::ContactHandler {
 public:
  static salsa::Parameters declare() {
    return {{"dwell", 1.0, 0.0, 60.0, "s", "time in view before a target counts as found"},
            {"drones_at_least", 0, 0, 1e6, "", "reset throws when the world has fewer drones (0: never)", 1}};
  }
  void reset(const salsa::WorldView& world) override {
    if (static_cast<double>(world.drone_positions().size()) < param("drones_at_least"))
      throw std::runtime_error("reset with " + std::to_string(world.drone_positions().size()) + " drones");
    dt_ = world.dt();
    in_view_.clear();
  }
  void on_contact(const salsa::ContactEvent& e, salsa::ContactActions& actions) override {
    if (!(dt_ > 0)) throw std::runtime_error("on_contact before reset");
    if (actions.world().time() != e.time)
      throw std::runtime_error("world time " + std::to_string(actions.world().time()) + " s is not the event's " +
                               std::to_string(e.time) + " s");
    if (e.kind != salsa::ContactKind::target_in_view) return;
    Seen& s = in_view_[e.other];
    if (s.last == e.time) return;  // another drone, same step
    s.last = e.time;
    s.total += dt_;
    if (s.total >= dwell_ - 1e-9) actions.mark_found(e.other, e.drone);
  }

 protected:
  void configure() override { dwell_ = param("dwell"); }

 private:
  struct Seen {
    double total = 0, last = -1;
  };
  double dwell_ = 0, dt_ = 0;
  std::unordered_map<std::uint32_t, Seen> in_view_;
};

}  // namespace

SALSA_CONTACT_HANDLER(TestDwell, "test_dwell", "Found after `dwell` s in view in all")
