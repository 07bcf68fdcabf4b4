// Registers a behavior of its own, then "test_dup" again: the whole file must be refused, so
// "test_dup_b_only" must not appear either.
#include <salsa/sdk.hpp>

namespace {
class DupB final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {2, 0}; }
};
}  // namespace

SALSA_BEHAVIOR(DupB, "test_dup_b_only", "Only in dup-b")
SALSA_BEHAVIOR(DupB, "test_dup", "test_dup from dup-b")
