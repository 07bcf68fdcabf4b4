// Sensor noise in the step: what noisy sensors make of the truth a drone perceives.
#include "salsa/core/model/simulation.hpp"

#include <algorithm>

#include "model/step_parallel.hpp"
#include "model/noise.hpp"

namespace salsa {

using namespace detail;

Vec2 Simulation::perceived_position(std::uint32_t id) const {
  const Vec2 p = drones_.positions[id];
  const double sd = groups_[drones_.groups[id]].noise.position;
  if (!(sd > 0)) return p;
  Rng rng = noise_rng(setup_.seed, NoiseStream::position_and_rays, steps_, id);
  return p + gaussian(rng, sd);
}

// What noisy sensors make of the truth. Everything is measured from where the drone is and placed
// around where it believes it is: its own position error moves the whole picture (neighbours, hits,
// targets) with it, so every distance stays |point − position| as without noise, and neighbour and
// ray noise are the errors of those relative measurements.
void Simulation::add_noise(Perception& me, Senses senses, Scratch& s) const {
  const Group::Noise& noise = groups_[me.group].noise;
  if (!noise.perceived() && !(noise.false_rate > 0)) return;  // another group's noise
  const Vec2 p = me.position;
  // The position error first (drawn whatever its sd), then one draw per ray hit, in ray order.
  Rng rng = noise_rng(setup_.seed, NoiseStream::position_and_rays, steps_, me.id);
  const Vec2 error = gaussian(rng, noise.position);
  me.position = p + error;
  if (noise.position > 0 || noise.obstacles > 0) {
    s.obstacles.assign(me.obstacles.begin(), me.obstacles.end());
    for (ObstacleHit& h : s.obstacles) {
      Vec2 offset = h.point - p;
      double d = h.distance;
      if (noise.obstacles > 0) {  // along the ray, within what a ray can report
        d = std::clamp(d + rng.normal(0, noise.obstacles), 0.0, me.obstacle_range);
        if (h.distance > 0) offset = offset * (d / h.distance);
      }
      h = {me.position + offset, d};
    }
    me.obstacles = s.obstacles;
  }
  if (noise.neighbours > 0) {
    Rng neighbours = noise_rng(setup_.seed, NoiseStream::neighbours, steps_, me.id);  // in neighbour order
    for (Neighbour& n : s.neighbours) {
      const Vec2 offset = n.position - p + gaussian(neighbours, noise.neighbours);
      n.position = me.position + offset;
      n.distance = offset.length();
    }
  } else if (noise.position > 0)
    for (Neighbour& n : s.neighbours) n.position += error;
  if (senses.targets) {
    if (noise.position > 0)
      for (TargetSeen& t : s.targets) t.position += error;
    if (noise.false_rate > 0)
      for (Vec2 offset : phantoms_[me.id]) s.targets.push_back({me.position + offset, offset.length(), TargetSeen::phantom, false});
    me.targets = s.targets;
  }
}

}  // namespace salsa
