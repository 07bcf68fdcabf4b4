// Its second registration throws (declare() fails): the loader must refuse the file whole, so the
// first registration must not appear either. SALSA_TEST_THROW picks what is thrown: 0 a
// std::runtime_error, 1 std::bad_alloc, 2 an int (not a std::exception).
#include <new>
#include <stdexcept>

#include <salsa/sdk.hpp>

#ifndef SALSA_TEST_THROW
#define SALSA_TEST_THROW 0
#endif

namespace {
class Fine final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};
class Broken final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    if (SALSA_TEST_THROW == 1) throw std::bad_alloc();
    if (SALSA_TEST_THROW == 2) throw 42;
    throw std::runtime_error("declare() failed on purpose");
  }
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};
}  // namespace

SALSA_BEHAVIOR(Fine, "test_registered_before_throw", "Must not survive the failed registration")
SALSA_BEHAVIOR(Broken, "test_broken", "declare() throws")
