// Registers "test_dup" (loaded first, so it wins) and a behavior of its own.
#include <salsa/sdk.hpp>

namespace {
class DupA final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {1, 0}; }
};
}  // namespace

SALSA_BEHAVIOR(DupA, "test_dup", "test_dup from dup-a")
SALSA_BEHAVIOR(DupA, "test_dup_a_only", "Only in dup-a")
