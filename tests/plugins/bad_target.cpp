// A target kind that hands the core bad data on request (its parameter `kind`): positions or radii a
// plugin must not return, or a place() that throws.
#include <cmath>
#include <limits>
#include <stdexcept>

#include <salsa/sdk.hpp>

namespace {

class TestBadTarget final : public salsa::TargetKind {
 public:
  static salsa::Parameters declare() {
    return {{"kind", 0, 0, 7, "",
             "0 good; 1 a NaN position; 2 a position outside the bounds; 3 radius -1; 4 radius NaN; 5 place() throws; "
             "6 one target too few; 7 an infinite position",
             1}};
  }
  double radius() const override {
    if (kind_ == 3) return -1;
    if (kind_ == 4) return std::numeric_limits<double>::quiet_NaN();
    return 1;
  }
  std::vector<salsa::Vec2> place(std::size_t count, const salsa::WorldView& world, salsa::Rng& rng) const override {
    if (kind_ == 5) throw std::runtime_error("lost the seed list");
    std::vector<salsa::Vec2> out = TargetKind::place(count, world, rng);
    const salsa::Rect b = world.bounds();
    if (!out.empty()) {
      if (kind_ == 1) out.back().x = std::numeric_limits<double>::quiet_NaN();
      if (kind_ == 2) out.back() = {b.max.x + 10, b.min.y};
      if (kind_ == 6) out.pop_back();
      if (kind_ == 7) out.back().y = -std::numeric_limits<double>::infinity();
    }
    return out;
  }

 protected:
  void configure() override { kind_ = static_cast<int>(param("kind")); }

 private:
  int kind_ = 0;
};

}  // namespace

SALSA_TARGET(TestBadTarget, "test_bad_target", "Test target kind: returns bad data of the kind asked for")
