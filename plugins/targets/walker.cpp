// Walkers: people on foot (a search-and-rescue task), found when a drone's camera disc overlaps the
// person (the default in_view), placed uniformly over free space (the default place), then walking at
// a steady speed on a correlated random walk: the heading wanders by a normal step each time step and,
// when the point `lookahead` m ahead is not free (an obstacle or the map's edge), turns to the nearest
// heading whose point is, trying each side in turn in steps of 22.5°. A walker whose next step is not
// free stays put that step and turns on.
#include <salsa/sdk.hpp>

#include <cmath>

namespace {

class Walker final : public salsa::TargetKind {
  salsa::Param radius_{this, "radius", 1.0, 0.1, 5.0, "m", "radius of a person (the disc a camera must overlap)"};
  salsa::Param speed_{this, "speed", 1.0, 0.1, 3.0, "m/s", "walking speed"};
  salsa::Param turn_{this, "turn", 0.5, 0.0, 5.0, "rad", "how fast the heading wanders: the standard deviation of its change over 1 s (over t s: times √t)"};
  salsa::Param lookahead_{this, "lookahead", 3.0, 0.0, 50.0, "m", "how far ahead a walker keeps clear of obstacles and the map's edge"};

  // The heading nearest `heading` whose point `lookahead` ahead is free, the side tried first drawn at
  // random; the heading itself, reversed, when none is.
  double clear_heading(salsa::Vec2 p, double heading, const salsa::WorldView& world, salsa::Rng& rng) const {
    auto free = [&](double h) { return world.is_free(p + salsa::Vec2::polar(lookahead_, h), radius_); };
    if (free(heading)) return heading;
    const double side = rng.chance(0.5) ? 1 : -1;
    for (int k = 1; k <= 8; ++k)
      for (double s : {side, -side})
        if (const double h = heading + s * k * salsa::pi / 8; free(h)) return h;
    return heading + salsa::pi;
  }

 public:
  double radius() const override { return radius_; }
  bool moves() const override { return true; }
  double max_speed() const override { return speed_; }

  // A walker's velocity is its heading at its walking speed (zero before its first step: it draws one).
  void move(std::span<salsa::Vec2> positions, std::span<salsa::Vec2> velocities, const salsa::WorldView& world,
            salsa::Rng& rng) const override {
    const double dt = world.dt(), wander = turn_ * std::sqrt(dt);
    for (std::size_t i = 0; i < positions.size(); ++i) {
      double heading = velocities[i] == salsa::Vec2{} ? rng.angle() : velocities[i].angle();
      heading = clear_heading(positions[i], heading + rng.normal(0, wander), world, rng);
      velocities[i] = salsa::Vec2::polar(speed_, heading);
      if (const salsa::Vec2 next = positions[i] + velocities[i] * dt; world.is_free(next, radius_)) positions[i] = next;
    }
  }
};

}  // namespace

SALSA_TARGET(Walker, "walker", "People walking (a correlated random walk that turns away from obstacles), found by camera overlap")
