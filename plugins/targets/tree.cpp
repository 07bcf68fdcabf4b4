// Trees: static discs, found when a drone's camera disc overlaps the tree (the default in_view) and
// placed uniformly over free space (the default place).
#include <salsa/sdk.hpp>

namespace {

class Tree final : public salsa::TargetKind {
  salsa::Param radius_{this, "radius", 5.0, 0.1, 100.0, "m", "radius of a tree's crown"};

 public:
  double radius() const override { return radius_; }
};

}  // namespace

SALSA_TARGET(Tree, "tree", "Trees, found when a drone's camera range overlaps the crown")
