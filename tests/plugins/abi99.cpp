// Built with SALSA_PLUGIN_ABI=99 (see tests/CMakeLists.txt): the loader must refuse it before calling
// anything in it.
#include <salsa/sdk.hpp>

namespace {
class TestAbi99 final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};
}  // namespace

SALSA_BEHAVIOR(TestAbi99, "test_abi99", "Must never be registered")
