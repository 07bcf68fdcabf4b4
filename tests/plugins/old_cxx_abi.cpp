// Built with -D_GLIBCXX_USE_CXX11_ABI=0 (see tests/CMakeLists.txt): std::string has another layout,
// so the loader must refuse it, in words, before calling anything in it.
#include <salsa/sdk.hpp>

namespace {
class OldAbi final : public salsa::Behavior {
 public:
  salsa::Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {}; }
};
}  // namespace

SALSA_BEHAVIOR(OldAbi, "test_old_cxx_abi", "Must never be registered")
