// A behavior that fails on request at a given simulated time, the ways a real plugin can: a
// segmentation fault, a call to std::exit, a thrown exception, an abort. What salsa owes the user
// then is a line naming the test and the plugin (and, with --isolate, the other tests going on).
#include <cstdlib>
#include <stdexcept>

#include <salsa/sdk.hpp>

namespace {

// A real SIGSEGV, also in the asan-ubsan build (where UBSan would report the null store first).
__attribute__((no_sanitize("undefined"), noinline)) void segfault() {
  volatile int* volatile wild = nullptr;  // volatile: the compiler cannot see it is null
  *wild = 1;
}

class TestCrash final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    return {{"mode", 0.0, 0.0, 4.0, "", "0: behave; 1: segfault; 2: std::exit(0); 3: throw; 4: abort", 1},
            {"at", 0.5, 0.0, 1e6, "s", "simulated time of the failure"}};
  }
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    if (mode_ == 0 || me.time < at_ || me.id != 0) return {1, 0};
    switch (mode_) {
      case 1: segfault(); break;
      case 2: std::exit(0);                // a plugin ending the process "successfully" mid-test
      case 3: throw std::runtime_error("crash plugin threw as asked");
      default: std::abort();
    }
    return {};
  }

 protected:
  void configure() override {
    mode_ = static_cast<int>(param("mode"));
    at_ = param("at");
  }

 private:
  int mode_ = 0;
  double at_ = 0;
};

}  // namespace

SALSA_BEHAVIOR(TestCrash, "test_crash", "Test behavior that segfaults, exits, throws or aborts at a given time")
