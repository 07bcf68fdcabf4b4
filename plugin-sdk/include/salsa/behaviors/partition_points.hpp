#pragma once
// The virtual points of dynamic space partitioning, shared by both versions (dynamic_space_partitioning
// and dynamic_space_partitioning_paper): one point per drone id, and the points of a behavior's members
// (its group's flying drones) repel each other until they spread evenly over the area. `PartitionPoints`
// holds every point at once (the `global` sharing); `HeardPoints` is one drone's own view over the radio.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "salsa/behavior.hpp"
#include "salsa/grid.hpp"

namespace salsa::behaviors {

class PartitionPoints {
 public:
  /// Forgets every point (a new run): the next `gather` seeds them at the drones.
  void clear() { points_.clear(); }

  /// Once a step, before `spread`: one point per drone id (a new id's point starts at its drone, the
  /// others keep theirs), and which drones are `behavior`'s members. True when the count changed.
  bool gather(const WorldView& world, const Behavior& behavior) {
    const auto drones = world.drone_positions();
    const std::size_t old = points_.size();
    if (old != drones.size()) {
      points_.resize(drones.size());
      for (std::size_t i = old; i < drones.size(); ++i) points_[i] = drones[i];
    }
    members_.clear();
    member_.assign(drones.size(), 0);
    for (std::uint32_t i = 0; i < drones.size(); ++i)
      if (salsa::is_member(world, behavior, i)) members_.push_back(i), member_[i] = 1;
    spacing_ = members_.empty() ? 0 : std::sqrt(world.bounds().area() / static_cast<double>(members_.size()));
    return old != drones.size();
  }

  /// Moves the members' points one step: each is pushed by point_speed · dt · clamp(Σ_j unit(pᵢ − pⱼ) ·
  /// (1 − d / R), 1) over the other members' points j within R = cutoff · spacing, then clamped into
  /// the bounds less `margin`. The pushes are computed from the old positions only, so the order of the
  /// points does not matter. With `clearance` > 0 a point keeps that far from obstacles (it slides
  /// along them, or stays); with 0 points are virtual and pass obstacles.
  void spread(const WorldView& world, const Rect& b, double point_speed, double cutoff, double margin, double clearance = 0) {
    if (members_.empty()) return;
    const double reach = cutoff * spacing_, step = point_speed * world.dt();
    margin = std::min({margin, b.width() / 2, b.height() / 2});
    scratch_.clear();
    for (std::uint32_t i : members_) scratch_.push_back(points_[i]);
    grid_.build(scratch_, reach);
    next_.resize(members_.size());
    for (std::uint32_t k = 0; k < members_.size(); ++k) {
      const std::uint32_t i = members_[k];
      const Vec2 p = points_[i];
      Vec2 push;
      grid_.query(p, reach, [&](std::uint32_t j, Vec2 q, double d2) {
        if (j == k) return;
        const double d = std::sqrt(d2);  // coincident points part along a fixed per-drone direction
        push += (d > 0 ? (p - q) / d : Vec2::polar(1, 2.39996 * i)) * (1 - d / reach);
      });
      const Vec2 m = p + push.clamped(1) * step;
      next_[k] = {std::clamp(m.x, b.min.x + margin, b.max.x - margin), std::clamp(m.y, b.min.y + margin, b.max.y - margin)};
      if (clearance > 0 && !world.is_free(next_[k], clearance) && world.is_free(p, clearance)) {
        const Vec2 along_x{next_[k].x, p.y}, along_y{p.x, next_[k].y};
        next_[k] = world.is_free(along_x, clearance) ? along_x : world.is_free(along_y, clearance) ? along_y : p;
      }
    }
    for (std::uint32_t k = 0; k < members_.size(); ++k) points_[members_[k]] = next_[k];
  }

  std::size_t size() const { return points_.size(); }  ///< one per drone id
  Vec2 operator[](std::uint32_t id) const { return points_[id]; }
  /// The members' ids this step, ascending, and whether drone `id` is one.
  std::span<const std::uint32_t> members() const { return members_; }
  bool is_member(std::uint32_t id) const { return id < member_.size() && member_[id]; }
  /// √(area / members), m: the spacing of points spread evenly (0 without members).
  double spacing() const { return spacing_; }

 private:
  std::vector<Vec2> points_, scratch_, next_;
  std::vector<std::uint32_t> members_;
  std::vector<char> member_;
  double spacing_ = 0;
  PointGrid grid_;
};

/// One drone's view of the points when they travel over the radio (`sharing` 1): its own point, which
/// only it moves, and the others' points as last heard. The spread is PartitionPoints::spread's for the
/// own point alone, pushed by the points heard within `timeout` s; the spacing counts those and itself.
class HeardPoints {
 public:
  bool seeded() const { return seeded_; }
  /// The own point starts at its drone (a new run, or a drone new to the group).
  void seed(Vec2 at) { own_ = at, seeded_ = true; }

  /// A point drone `sender` broadcast at `time` (s); an older one than what is known is ignored.
  void hear(std::uint32_t sender, Vec2 point, double time) {
    if (sender >= heard_.size()) heard_.resize(sender + 1, {{}, -std::numeric_limits<double>::infinity()});
    if (time > heard_[sender].time) heard_[sender] = {point, time};
  }

  /// Once a step, before `spread`: the known points (own id `self`, and those heard at or after
  /// now − timeout), ascending by id, and the spacing √(area / their count).
  void refresh(std::uint32_t self, double now, double timeout, double area) {
    known_.clear();
    bool own_in = false;
    for (std::uint32_t j = 0; j < heard_.size(); ++j) {
      if (j == self) own_in = true, known_.emplace_back(self, own_);
      else if (heard_[j].time >= now - timeout) known_.emplace_back(j, heard_[j].point);
    }
    if (!own_in) known_.emplace_back(self, own_);  // heard only lower ids: the own point is the last
    spacing_ = std::sqrt(area / static_cast<double>(known_.size()));
  }

  /// Moves the own point one step, as PartitionPoints::spread moves each point (same push, bounds and
  /// clearance), from the known points.
  void spread(std::uint32_t self, const WorldView& world, const Rect& b, double point_speed, double cutoff, double margin,
              double clearance = 0) {
    const double reach = cutoff * spacing_, step = point_speed * world.dt();
    margin = std::min({margin, b.width() / 2, b.height() / 2});
    const Vec2 p = own_;
    Vec2 push;
    for (const auto& [j, q] : known_) {
      if (j == self) continue;
      const double d2 = distance_squared(p, q);
      if (d2 > reach * reach) continue;
      const double d = std::sqrt(d2);  // coincident points part along a fixed per-drone direction
      push += (d > 0 ? (p - q) / d : Vec2::polar(1, 2.39996 * self)) * (1 - d / reach);
    }
    const Vec2 m = p + push.clamped(1) * step;
    Vec2 next{std::clamp(m.x, b.min.x + margin, b.max.x - margin), std::clamp(m.y, b.min.y + margin, b.max.y - margin)};
    if (clearance > 0 && !world.is_free(next, clearance) && world.is_free(p, clearance)) {
      const Vec2 along_x{next.x, p.y}, along_y{p.x, next.y};
      next = world.is_free(along_x, clearance) ? along_x : world.is_free(along_y, clearance) ? along_y : p;
    }
    own_ = next;
  }

  Vec2 own() const { return own_; }
  /// The points this drone knows, its own among them, ascending by id (as of the last refresh).
  std::span<const std::pair<std::uint32_t, Vec2>> known() const { return known_; }
  /// √(area / known points), m.
  double spacing() const { return spacing_; }

 private:
  struct Heard {
    Vec2 point;
    double time;  // s, when it was sent
  };
  Vec2 own_;
  bool seeded_ = false;
  double spacing_ = 0;
  std::vector<Heard> heard_;  // by sender id
  std::vector<std::pair<std::uint32_t, Vec2>> known_;
};

}  // namespace salsa::behaviors
