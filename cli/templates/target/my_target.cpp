// my_target: a salsa target kind. Targets are discs that drones search for; these are small or hidden,
// so a drone sees one only within `visibility` × its camera range. Placement is the default:
// uniform over free space (override place() to cluster them).
#include <salsa/sdk.hpp>

namespace {

class MyTarget final : public salsa::TargetKind {
  // Each parameter once: name, default, min, max, unit, meaning; it reads as a double.
  salsa::Param radius_{this, "radius", 2.0, 0.1, 100.0, "m", "radius of a target"};
  salsa::Param visibility{this, "visibility", 0.5, 0.0, 1.0, "", "fraction of the camera range within which a target is seen"};

 public:
  double radius() const override { return radius_; }
  bool in_view(double distance, double camera_range) const override {
    return distance < visibility * camera_range + radius_;
  }
};

}  // namespace

SALSA_TARGET(MyTarget, "my_target", "Small targets, seen within part of the camera range")
