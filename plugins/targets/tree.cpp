// Trees: static discs, found when a drone's camera disc overlaps the tree (the default in_view) and
// placed uniformly over free space (the default place).
#include <salsa/sdk.hpp>

namespace {

class Tree final : public salsa::TargetKind {
 public:
  static salsa::Parameters declare() {
    return {{"radius", 5.0, 0.1, 100.0, "m", "radius of a tree's crown"}};
  }
  double radius() const override { return radius_; }

 protected:
  void configure() override { radius_ = param("radius"); }

 private:
  double radius_ = 5;
};

}  // namespace

SALSA_TARGET(Tree, "tree", "Trees, found when a drone's camera range overlaps the crown")
