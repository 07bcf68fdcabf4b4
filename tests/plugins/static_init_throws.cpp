// A plugin whose static initialiser fails while the library is loaded (inside dlopen), before any
// registration runs: the loader must refuse this file alone, naming it, and load the others.
// SALSA_TEST_STATIC_INIT picks how: 0 throws, 1 calls std::exit(3), 2 aborts.
#include <cstdlib>
#include <stdexcept>

#ifndef SALSA_TEST_STATIC_INIT
#define SALSA_TEST_STATIC_INIT 0
#endif

#include <salsa/sdk.hpp>

namespace {

struct Exploding {
  Exploding() {
    if (SALSA_TEST_STATIC_INIT == 1) std::exit(3);
    if (SALSA_TEST_STATIC_INIT == 2) std::abort();
    throw std::runtime_error("static init exploded");
  }
};
const Exploding exploding;

class Never final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};

}  // namespace

SALSA_BEHAVIOR(Never, "test_static_init", "Never registered: its static initialiser throws")
