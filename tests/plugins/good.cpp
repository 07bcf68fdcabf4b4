// A well-formed test plugin: a tiny behavior whose decision shows its parameter, and one whose
// configure() throws on request (exceptions from plugin code, of any type, must come back naming the
// plugin).
#include <new>
#include <stdexcept>

#include <salsa/sdk.hpp>

namespace {

class TestGood final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() { return {{"gain", 2.0, 0.0, 10.0, "m/s", "x component of every decision"}}; }
  // Steers along +x by `gain` and along +y by the drone's id, so a test sees both the parameter and
  // the perception it was given.
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override { return {gain_, static_cast<double>(me.id)}; }

 protected:
  void configure() override { gain_ = param("gain"); }

 private:
  double gain_ = 0;
};

class TestThrows final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    return {{"explode", 0.0, 0.0, 3.0, "", "configure() throws 1: std::runtime_error, 2: std::bad_alloc, 3: an int", 1}};
  }
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }

 protected:
  void configure() override {
    if (param("explode") == 1) throw std::runtime_error("exploded as asked");
    if (param("explode") == 2) throw std::bad_alloc();
    if (param("explode") == 3) throw 42;
  }
};

}  // namespace

SALSA_BEHAVIOR(TestGood, "test_good", "Test behavior: steers (gain, id)")
SALSA_BEHAVIOR(TestThrows, "test_throws", "Test behavior whose configure() throws when explode > 0")
