// Its second registration throws (declare() fails): the loader must refuse the file whole, so the
// first registration must not appear either.
#include <stdexcept>

#include <salsa/sdk.hpp>

namespace {
class Fine final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};
class Broken final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() { throw std::runtime_error("declare() failed on purpose"); }
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};
}  // namespace

SALSA_BEHAVIOR(Fine, "test_registered_before_throw", "Must not survive the failed registration")
SALSA_BEHAVIOR(Broken, "test_broken", "declare() throws")
