// A behavior built twice by the test suite (SALSA_TEST_VERSION 1 and 2), for hot reload in the desktop:
// version 1 flies every drone along +x, version 2 along -x and declares one more parameter.
#include <string>

#include <salsa/sdk.hpp>

#ifndef SALSA_TEST_VERSION
#define SALSA_TEST_VERSION 1
#endif

namespace {

class TestReload final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    return {{"speed_fraction", 0.5, 0, 1, "", "fraction of max speed to fly at"},
#if SALSA_TEST_VERSION == 2
            {"added_in_v2", 3, 0, 10, "", "a parameter only version 2 declares"},
#endif
    };
  }
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    const double direction = SALSA_TEST_VERSION == 1 ? 1 : -1;
    return salsa::Vec2{direction * param("speed_fraction") * me.max_speed, 0} - me.velocity;
  }
  std::string inspect(std::uint32_t) const override { return "test_reload version " + std::to_string(SALSA_TEST_VERSION); }
};

}  // namespace

SALSA_BEHAVIOR(TestReload, "test_reload", "Flies along +x (version 1) or -x (version 2)")
