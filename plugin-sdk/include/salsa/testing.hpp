#pragma once
// A unit fixture for plugin authors: build one drone's Perception by hand and call `decide`, no
// simulation and no library needed. For a behavior with shared state (prepare), many drones, a map,
// targets or metrics, use the stepping simulation of salsa/fixture.hpp.
//
//   salsa::testing::Scene scene;                    // a "small" drone at the origin, at rest
//   scene.neighbour({10, 0}, {1, 0});               // another drone 10 m east, flying east
//   Flocking flocking;
//   salsa::Vec2 a = scene.decide(flocking);         // steering for this step (m/s)
#include <vector>

#include "salsa/sdk.hpp"

namespace salsa::testing {

class Scene {
 public:
  Scene() {
    me_.max_speed = 10;
    me_.max_force = 0.3;
    me_.radius = 1;
    me_.mass = 1.5;
    me_.camera_range = 15;
    me_.obstacle_range = 50.2;
    me_.detection_range = 134;
    me_.dt = 1.0 / 60;
  }
  /// The drone's own state and properties; edit freely (ranges, max speed, time, ...).
  Perception& me() { return me_; }
  /// Puts the drone at `position` flying at `velocity` over the ground (m, m/s).
  Scene& at(Vec2 position, Vec2 velocity = {}) {
    me_.position = position;
    me_.velocity = velocity;
    me_.air_velocity = velocity - me_.wind;
    return *this;
  }
  /// The wind where the drone is (m/s; none unless set): Perception::wind, and what step() flies in.
  /// The ground velocity stays; the air velocity becomes ground − wind.
  Scene& wind(Vec2 velocity) {
    me_.wind = velocity;
    me_.air_velocity = me_.velocity - velocity;
    return *this;
  }
  Scene& neighbour(Vec2 position, Vec2 velocity = {}) {
    neighbours_.push_back({position, velocity, 0, static_cast<std::uint32_t>(neighbours_.size() + 1)});
    return *this;
  }
  Scene& obstacle(Vec2 point) {
    obstacles_.push_back({point, 0});
    return *this;
  }
  Scene& target(Vec2 position, bool found = false) {
    targets_.push_back({position, 0, static_cast<std::uint32_t>(targets_.size()), found});
    return *this;
  }
  /// The Perception as the core would hand it to `decide` (valid while the Scene lives).
  const Perception& perception() {
    for (auto& n : neighbours_) n.distance = distance(n.position, me_.position);  // wherever `at` put me
    for (auto& o : obstacles_) o.distance = distance(o.point, me_.position);
    for (auto& t : targets_) t.distance = distance(t.position, me_.position);
    me_.neighbours = neighbours_;
    me_.obstacles = obstacles_;
    me_.targets = targets_;
    return me_;
  }
  /// One `decide` for this drone (id 0). The first time, a behavior without parameter values gets its
  /// declared defaults and memory for one drone. The random stream goes on from call to call, as a
  /// drone's does in a run (`seed` picks the stream at the first call).
  template <class B>
  Vec2 decide(B& behavior, std::uint64_t seed = 1) {
    if (!reset_) {
      if (behavior.parameters().items().empty()) behavior.set_parameters(ParameterValues(detail::declared_parameters<B>()));
      behavior.reset(1);
      rng_ = Rng(seed, 0);
      reset_ = true;
    }
    return static_cast<Behavior&>(behavior).decide(perception(), rng_);
  }
  /// decide, then fly the step as the core does without physics: air velocity = velocity − wind +
  /// steering, clamped to max speed; velocity = air velocity + wind; position += velocity × dt;
  /// time += dt. Neighbours, obstacles, targets and the wind stay as they are.
  template <class B>
  Vec2 step(B& behavior, std::uint64_t seed = 1) {
    const Vec2 steering = decide(behavior, seed);
    me_.air_velocity = (me_.velocity - me_.wind + steering).clamped(me_.max_speed);  // me().velocity may have been edited
    me_.velocity = me_.air_velocity + me_.wind;
    me_.position += me_.velocity * me_.dt;
    me_.time += me_.dt;
    return steering;
  }

 private:
  Perception me_;
  std::vector<Neighbour> neighbours_;
  std::vector<ObstacleHit> obstacles_;
  std::vector<TargetSeen> targets_;
  Rng rng_{1, 0};
  bool reset_ = false;
};

}  // namespace salsa::testing
