// Registers "test_twice" twice inside one library: the second registration alone is refused, the
// first and "test_once" load.
#include <salsa/sdk.hpp>

namespace {
class First final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {1, 0}; }
};
class Second final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {2, 0}; }
};
}  // namespace

SALSA_BEHAVIOR(First, "test_twice", "First registration: kept")
SALSA_BEHAVIOR(Second, "test_twice", "Second registration: refused")
SALSA_BEHAVIOR(First, "test_once", "Registered once")
