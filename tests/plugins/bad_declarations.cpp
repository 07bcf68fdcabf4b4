// One behavior per bad declaration (or bad registration name), and one good one: each bad
// registration is refused with its reason, the good one loads.
#include <cmath>
#include <limits>

#include <salsa/sdk.hpp>

namespace {

template <int N>
class Declares final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    switch (N) {
      case 0: return {{"gain", 1.0, 0.0, 10.0, "", "fine"}};
      case 1: return {{"gain", 5.0, 10.0, 0.0, "", "min > max"}};
      case 2: return {{"gain", 12.0, 0.0, 10.0, "", "default outside"}};
      case 3: return {{"gain", nan, 0.0, 10.0, "", "NaN default"}};
      case 4: return {{"gain", 1.0, 0.0, inf, "", "infinite max"}};
      case 5: return {{"", 1.0, 0.0, 10.0, "", "empty name"}};
      case 6: return {{"gain", 1.0, 0.0, 10.0, "", "first"}, {"gain", 2.0, 0.0, 10.0, "", "second"}};
      case 7: return {{"count", 2.5, 0.0, 10.0, "", "integer with a fraction", 1}};
      case 8: return {{"two words", 1.0, 0.0, 10.0, "", "not a name"}};
      case 9: return {{"gain", 1.0, 0.0, 10.0, "", "negative step", -1}};
    }
    return {};
  }
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};

}  // namespace

SALSA_BEHAVIOR(Declares<0>, "test_decl_ok", "Declares a valid parameter")
SALSA_BEHAVIOR(Declares<1>, "test_decl_min_above_max", "min > max")
SALSA_BEHAVIOR(Declares<2>, "test_decl_default_outside", "default outside its range")
SALSA_BEHAVIOR(Declares<3>, "test_decl_nan", "NaN default")
SALSA_BEHAVIOR(Declares<4>, "test_decl_inf", "infinite max")
SALSA_BEHAVIOR(Declares<5>, "test_decl_empty_name", "a parameter without a name")
SALSA_BEHAVIOR(Declares<6>, "test_decl_duplicate", "the same parameter twice")
SALSA_BEHAVIOR(Declares<7>, "test_decl_fraction", "integer parameter with a fractional default")
SALSA_BEHAVIOR(Declares<8>, "test_decl_bad_name", "parameter name with a space")
SALSA_BEHAVIOR(Declares<9>, "test_decl_negative_step", "negative step")
SALSA_BEHAVIOR(Declares<0>, "", "registration without a name")
SALSA_BEHAVIOR(Declares<0>, "../escape", "registration name that is a path")
