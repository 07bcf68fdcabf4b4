// A behavior that writes its outbox by hand instead of through broadcast: a size past its slot (the
// next drone's data, or far past the room) or a room moved elsewhere. The core must refuse to read
// it, failing the test and naming the behavior.
#include <array>

#include <salsa/sdk.hpp>

namespace {

class TestOutbox final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    return {{"size", 3, 0, 1e9, "doubles", "the size written into the outbox after a broadcast of 2"},
            {"move", 0, 0, 1, "", "1: point the outbox's room at the behavior's own array of 8"}};
  }
  std::size_t message_size() const override { return 2; }
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    const std::array<double, 2> payload{static_cast<double>(me.id), 1};
    me.broadcast(payload);
    if (me.outbox) {
      if (param("move") > 0) me.outbox->room = elsewhere_;
      me.outbox->size = static_cast<std::size_t>(param("size"));
    }
    return {0.1, 0};
  }

 private:
  std::array<double, 8> elsewhere_{};
};

}  // namespace

SALSA_BEHAVIOR(TestOutbox, "test_outbox", "Test behavior: writes its outbox's size or room by hand")
