// Sense: the drone grid, each drone's obstacle rays and the targets in its camera's view.
#include "salsa/core/model/simulation.hpp"

#include <algorithm>
#include <cmath>

#include "model/plugin_call.hpp"
#include "model/step_parallel.hpp"
#include "model/noise.hpp"

namespace salsa {

using namespace detail;

// A drone's targets come from a short list kept across steps rather than from the grid's cells, which
// lie in three rows rarely in cache. The list holds the targets within reach + margin of where it was
// made, in the grid's order; while the drone stays within the margin of that spot every target within
// reach is on it (the triangle inequality, with 1 % to spare for rounding), so filtering it gives the
// grid's answer: the same distances in the same order. At full speed a drone remakes its list about
// every 30 steps. Moving targets (rebuilt into the grid every step) may have come closer since: the
// list then holds while the drone's distance from the spot plus the farthest a target went since
// (Targets::travel) stays within the margin; it is read at the targets' positions now, in id order
// (the grid's order changes as they move, and `sighted` needs one order from step to step).
// `Record` is a Simulation::Sensed, `Targets` Simulation::Targets.
template <class Record, class Targets, class Fn>
void targets_in_reach(const Targets& targets, Record& d, Vec2 p, double reach, Fn&& fn) {
  if (!(reach > 0)) return;  // the grid finds nothing closer than 0
  const double margin = reach / 4;
  const double r2 = reach * reach;
  if (!targets.moving) {
    if (d.reach != reach || !(distance_squared(p, d.anchor) <= 0.98 * margin * margin)) {
      d.anchor = p;
      d.reach = reach;
      d.near.clear();
      targets.grid.query(p, reach + margin, [&](std::uint32_t t, Vec2 at, double) { d.near.push_back({at, t}); });
    }
    for (const auto& c : d.near)
      if (const double d2 = distance_squared(c.at, p); d2 < r2) fn(c.id, c.at, d2);
    return;
  }
  if (d.reach != reach || !(std::sqrt(distance_squared(p, d.anchor)) + (targets.travel - d.travel) <= 0.99 * margin)) {
    d.anchor = p;
    d.reach = reach;
    d.travel = targets.travel;
    d.near.clear();
    targets.grid.query(p, reach + margin, [&](std::uint32_t t, Vec2 at, double) { d.near.push_back({at, t}); });
    std::sort(d.near.begin(), d.near.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  }
  for (const auto& c : d.near) {
    const Vec2 at = targets.positions[c.id];
    if (const double d2 = distance_squared(at, p); d2 < r2) fn(c.id, at, d2);
  }
}

// Sense: index the drones for neighbour queries, cast each flying drone's obstacle rays against static
// geometry and find the targets in its camera view. Neighbours are gathered per drone in `decide`,
// where they stay in cache. With detection noise a target in view may be missed (then neither the
// behavior nor the contact handlers hear of it this step) and false detections appear (the behavior
// alone sees them); the other noise is added where the perception is built (add_noise).
void Simulation::sense() {
  drone_grid_.build(drones_.positions, grid_range_ / 2);  // 5×5 cells of R/2 cover less than 3×3 of R
  sensed_.resize(drones_.positions.size());
  const TargetKind* kind = targets_.states.empty() ? nullptr : setup_.target_kind.get();
  bool false_detections = false;
  for (const Group& g : groups_) false_detections = false_detections || g.noise.false_rate > 0;
  if (false_detections) phantoms_.resize(drones_.positions.size());
  // A few drones ahead in grid order, their records, then what those point to: drone ids are scattered
  // in grid order, and with 100,000 drones each record would otherwise be a miss waited on.
  auto ahead = [&](std::uint32_t j, int stage) {
    const Sensed& d = sensed_[j];
    if (stage == 0) {
      for (const char* at = reinterpret_cast<const char*>(&d); at < reinterpret_cast<const char*>(&d + 1); at += 64) __builtin_prefetch(at);
      __builtin_prefetch(reinterpret_cast<const char*>(&d + 1) - 1);
    } else {
      __builtin_prefetch(d.near.data());
      __builtin_prefetch(d.seen.data());  // `before` once swapped
    }
  };
  parallel_->for_each(drone_grid_.cell_order(), [&](std::uint32_t i, Scratch& s) {
    Sensed& sensed = sensed_[i];
    std::swap(sensed.seen, sensed.before);
    std::vector<TargetSeen>& seen = sensed.seen;
    seen.clear();
    sensed.entered.clear();
    if (false_detections) phantoms_[i].clear();
    if (drones_.status[i] != DroneStatus::flying) return void(drones_.sensing.hit_counts[i] = 0);  // a stopped drone sees nothing
    const Group& group = groups_[drones_.groups[i]];
    const DroneProperties& cfg = group.properties;
    const Vec2 p = drones_.positions[i];
    std::uint8_t count = 0;
    s.segment_ids.clear();
    if (!group.rays.empty()) geometry_.candidates(p, cfg.obstacle_range, s.segment_ids);  // a drone without rays looks for no walls
    if (!s.segment_ids.empty())
      for (Vec2 direction : group.rays)
        if (auto hit = geometry_.ray_cast(p, direction, cfg.obstacle_range, s.segment_ids))
          drones_.sensing.hits[i * ray_slots_ + count++] = *hit;
    drones_.sensing.hit_counts[i] = count;
    const Group::Noise& noise = group.noise;
    // Whether each target came into view: `before` is in the same grid order, so a target still in
    // view lies past the last one met there.
    const std::vector<TargetSeen>& before = sensed.before;
    std::size_t from = 0;
    auto sighted = [&](std::uint32_t t, Vec2 at, double d) {
      seen.push_back({at, d, t, false});  // found: filled in where a behavior asks (perceive)
      std::size_t k = from;
      while (k < before.size() && before[k].id != t) ++k;
      if (k < before.size()) from = k + 1;
      else sensed.entered.push_back(static_cast<std::uint32_t>(seen.size() - 1));
    };
    if (kind && drones_.fleet.camera[i] && noise.miss > 0) {
      Rng rng = noise_rng(setup_.seed, NoiseStream::misses, steps_, i);  // one draw per target in view, in grid order
      targets_in_reach(targets_, sensed, p, group.reach, [&](std::uint32_t t, Vec2 at, double d2) {
        const double d = std::sqrt(d2);
        if (plugin_call(target_kind, 0, [&] { return kind->in_view(d, cfg.camera_range); }) && !rng.chance(noise.miss))
          sighted(t, at, d);
      });
    } else if (kind && drones_.fleet.camera[i])
      targets_in_reach(targets_, sensed, p, group.reach, [&](std::uint32_t t, Vec2 at, double d2) {
        const double d = std::sqrt(d2);
        if (plugin_call(target_kind, 0, [&] { return kind->in_view(d, cfg.camera_range); })) sighted(t, at, d);
      });
    if (noise.false_rate > 0 && drones_.fleet.camera[i]) {  // anywhere in the camera's disc, with or without targets
      Rng rng = noise_rng(setup_.seed, NoiseStream::phantoms, steps_, i);
      for (std::size_t k = poisson(rng, noise.false_rate * setup_.dt); k > 0; --k) {
        const double angle = rng.angle();  // drawn first, in its own statement: the order is not the compiler's
        phantoms_[i].push_back(Vec2::polar(cfg.camera_range * std::sqrt(rng.uniform()), angle));
      }
    }
  }, ahead);
  if (false_detections)
    for (const auto& phantoms : phantoms_) false_detections_ += phantoms.size();
}

void Simulation::Drones::Sensing::columns(std::vector<StateColumn>& out) const {
  out.push_back(StateColumn::of("obstacle_hits", "", "sensing", "how many of its obstacle rays hit something in the last sense", hit_counts));
}

}  // namespace salsa
