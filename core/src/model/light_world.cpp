#include "model/light_world.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace salsa {

namespace {

constexpr std::size_t grain = 1024;  // drones per task: a move costs well under a microsecond

Vec2 closest_point(Vec2 p, const Segment& s) {
  const Vec2 e = s.b - s.a;
  const double l2 = e.length_squared();
  const double t = l2 > 0 ? std::clamp((p - s.a).dot(e) / l2, 0.0, 1.0) : 0.0;
  return s.a + e * t;
}

/// The wall's normal as seen from p: the unit vector from s's closest point to p.
Vec2 normal_from(Vec2 p, const Segment& s) {
  const Vec2 n = p - closest_point(p, s);
  if (const double l = n.length(); l > 0) return n / l;
  const Vec2 e = s.b - s.a;  // p on the segment, which the sweep never allows: any fixed side
  const double l = e.length();
  return l > 0 ? Vec2{-e.y / l, e.x / l} : Vec2{1, 0};
}

/// The first fraction t of the move p → p + d at which p comes within r of s (the ray against the
/// capsule of radius r around s); 1 when it never does. A start already within r (rounding leaves a
/// drone resting on a wall a hair inside) blocks only a move that goes closer: the distance to a
/// segment is convex along a line, so one that does not start closing in never does.
double sweep(Vec2 p, Vec2 d, double r, const Segment& s) {
  const Vec2 off = p - closest_point(p, s);
  if (off.length_squared() < r * r) return off.dot(d) < -1e-9 * off.length() * d.length() ? 0.0 : 1.0;
  double best = 1;
  const Vec2 e = s.b - s.a;
  if (const double len = e.length(); len > 0) {  // the side of the capsule facing p
    const Vec2 m{-e.y / len, e.x / len};
    const double h = (p - s.a).dot(m), dh = d.dot(m);
    if (h * dh < 0 && std::abs(dh) > 1e-9 * d.length()) {  // closing in, not grazing (rounding)
      const double t = ((h > 0 ? r : -r) - h) / dh;
      const double u = (p + d * t - s.a).dot(e) / (len * len);
      if (t >= 0 && t < best && u >= 0 && u <= 1) best = t;
    }
  }
  for (const Vec2 q : {s.a, s.b}) {  // its round ends
    const Vec2 f = p - q;
    const double a = d.length_squared(), b = f.dot(d), c = f.length_squared() - r * r;
    if (a == 0 || b >= -1e-9 * std::sqrt(a * f.length_squared())) continue;  // not closing in on q (or grazing)
    const double disc = b * b - a * c;
    if (disc < 0) continue;
    const double t = (-b - std::sqrt(disc)) / a;
    if (t >= 0 && t < best) best = t;
  }
  return best;
}

/// v without its component into the wall of normal n (an inelastic contact, as Box2D's).
void remove_into(Vec2& v, Vec2 n) {
  if (const double into = v.dot(n); into < 0) v -= n * into;
}

}  // namespace

template <class Fn>
void LightWorld::for_each(std::size_t n, Fn&& fn) {
  if (n <= grain) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  arena_.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
    });
  });
}

// Ids come in order (the Simulation adds drone `positions_.size()` each time), so they are the slots.
void LightWorld::add_drone(std::uint32_t, Vec2 position, Vec2 velocity, const DroneConfig& config, bool enabled) {
  positions_.push_back(position);
  velocities_.push_back(enabled ? velocity : Vec2{});
  radius_.push_back(config.radius);
  mass_.push_back(config.mass);
  enabled_.push_back(enabled);
  on_wall_.push_back(0);
  min_radius_ = positions_.size() == 1 ? config.radius : std::min(min_radius_, config.radius);
  max_radius_ = std::max(max_radius_, config.radius);
}

void LightWorld::remove_drones_from(std::size_t n) {
  if (n >= positions_.size()) return;
  for (auto* v : {&positions_, &velocities_}) v->resize(n);
  for (auto* v : {&radius_, &mass_}) v->resize(n);
  for (auto* v : {&enabled_, &on_wall_}) v->resize(n);
  std::erase_if(touching_, [&](const Pair& p) { return p.second >= n; });
  std::erase_if(pairs_, [&](const Pair& p) { return p.second >= n; });
  max_radius_ = radius_.empty() ? 0 : *std::max_element(radius_.begin(), radius_.end());
  min_radius_ = radius_.empty() ? 0 : *std::min_element(radius_.begin(), radius_.end());
}

void LightWorld::disable(std::uint32_t id) {
  if (!enabled_[id]) return;
  enabled_[id] = 0;
  velocities_[id] = {};
  on_wall_[id] = 0;  // its pairs go with the next step's, which skip it
}

void LightWorld::set_velocities(std::span<const Vec2> velocities, std::span<const DroneStatus> status) {
  for (std::size_t i = 0; i < positions_.size(); ++i)
    if (status[i] == DroneStatus::flying) velocities_[i] = velocities[i];
}

void LightWorld::read_back(std::span<Vec2> positions, std::span<Vec2> velocities) const {
  std::copy(positions_.begin(), positions_.end(), positions.begin());
  std::copy(velocities_.begin(), velocities_.end(), velocities.begin());
}

bool LightWorld::move(const StaticGeometry& geometry, std::uint32_t i, Vec2 d, Vec2& v) {
  thread_local std::vector<std::uint32_t> ids;
  const auto segments = geometry.segments();
  // Walls within `rest` hold the drone: it slides along them (rounding leaves one a hair off, or in).
  const double r = radius_[i], near = r + slop(r), rest = r * (1 + 1e-9) + 1e-9;
  Vec2 p = positions_[i];
  bool looked = false;  // ids hold every segment within `near` of p
  // A wall met ends the move's part into it and the rest slides along it; a third wall in one step (a
  // corner) ends the move.
  for (int pass = 0; pass < 3; ++pass) {
    const double length = d.length();
    if (!(length > 0)) break;
    // Every segment within `near` of the path. Removing a component into a wall keeps the path within
    // the same disc (Thales: |d' − d/2| = |d|/2), so this list serves the slide too.
    geometry.candidates(p + d / 2, length / 2 + near, ids);
    looked = true;
    if (ids.empty()) {
      p += d;
      break;
    }
    for (std::uint32_t id : ids)  // walls it rests on: it slides along them
      if (segment_distance(p, segments[id]) < rest) {
        const Vec2 n = normal_from(p, segments[id]);
        remove_into(d, n);
        remove_into(v, n);
      }
    double t = 1;
    std::uint32_t hit = 0;
    for (std::uint32_t id : ids)
      if (const double s = sweep(p, d, r, segments[id]); s < t) t = s, hit = id;
    p += d * t;
    if (t == 1) break;
    const Vec2 n = normal_from(p, segments[hit]);
    d = d * (1 - t);
    remove_into(d, n);
    remove_into(v, n);
    looked = false;  // the rest of the move is a new path
  }
  positions_[i] = p;
  if (!looked) geometry.candidates(p, near, ids);
  return std::any_of(ids.begin(), ids.end(), [&](std::uint32_t id) { return segment_distance(p, segments[id]) < near; });
}

void LightWorld::advance(const StaticGeometry& geometry, double dt, int, int) {
  begun_.clear();
  const std::size_t n = positions_.size();
  wall_now_.assign(n, 0);
  stop_closing(dt);
  // Each drone's own move: reads and writes its own slots only.
  for_each(n, [&](std::size_t i) {
    if (!enabled_[i]) return;
    Vec2 v = velocities_[i];
    wall_now_[i] = move(geometry, static_cast<std::uint32_t>(i), v * dt, v);
    velocities_[i] = v;
  });
  separate(geometry);

  // Contacts begun: drone by drone, a wall first, then the drones of higher id it began touching.
  std::size_t k = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (wall_now_[i] && !on_wall_[i]) begun_.push_back({ContactKind::drone_obstacle, i, 0, positions_[i], 0});
    for (; k < fresh_.size() && fresh_[k].first == i; ++k) {
      const std::uint32_t j = fresh_[k].second;
      begun_.push_back({ContactKind::drone_drone, i, j, (positions_[i] + positions_[j]) / 2, 0});
    }
  }
  std::swap(on_wall_, wall_now_);
}

// Before the move, as Box2D's velocity solver does: drones that touch stop closing in on each other.
// Each pair's closing speed along the line between them is taken off both, by mass share. The pairs are
// visited in their sorted order, each seeing what the pairs before it did (Gauss–Seidel, as Box2D's
// solver): the order is the ids', never the threads', and a pile converges where a Jacobi pass,
// reading only the last pass, would leave its inner drones pressed (measured in test_light).
void LightWorld::stop_closing(double dt) {
  // Positions hold still here, so each pair's direction and allowed closing speed are found once.
  contacts_.clear();
  for (const auto& [a, b] : pairs_) {
    if (!enabled_[a] || !enabled_[b]) continue;
    const Vec2 ab = positions_[a] - positions_[b];
    const double dist = ab.length();
    const Vec2 u = dist > 0 ? ab / dist : Vec2{1, 0};  // on top of each other: apart along x, by id
    // A pair not yet touching may close the gap between them in this step, no more (a speculative
    // contact): so the move itself makes almost no overlap for the pushes to undo.
    contacts_.push_back({{a, b}, u, -std::max(dist - radius_[a] - radius_[b], 0.0) / dt});
  }
  for (int pass = 0; pass < solver_passes; ++pass) {
    bool any = false;
    for (const auto& [pair, u, allowed] : contacts_) {
      const auto [a, b] = pair;
      const double closing = (velocities_[a] - velocities_[b]).dot(u) - allowed, total = mass_[a] + mass_[b];
      if (!(closing < -1e-12)) continue;
      velocities_[a] -= u * (closing * mass_[b] / total);
      velocities_[b] += u * (closing * mass_[a] / total);
      any = true;
    }
    if (!any) break;
  }
}

// The pairs within reach (radii + margin), sorted. A drone with more neighbours than neighbour_cap keeps
// its nearest (ties by id), and a pair stays if either drone keeps the other: at most n × the cap pairs
// however full the pile, and, below the cap, every pair as before. Drones report only higher ids; when
// one is capped, it reports its kept neighbours of lower ids too, and a second pass adds the pairs of
// uncapped drones with capped ones of lower id that did not keep them.
void LightWorld::find_pairs(double margin) {
  const std::size_t n = positions_.size(), cap = neighbour_cap(min_radius_, max_radius_);
  grid_.build(positions_, 2 * max_radius_ + margin);
  capped_.assign(n, 0);
  auto neighbours = [&](std::size_t i, std::vector<Near>& out) {
    out.clear();
    const double ri = radius_[i];
    grid_.query(positions_[i], ri + max_radius_ + margin, [&](std::uint32_t j, Vec2, double d2) {
      const double near = ri + radius_[j] + margin;
      if (j != i && enabled_[j] && d2 < near * near) out.push_back({d2, j});
    });
  };
  for_each(n, [&](std::size_t i) {
    if (!enabled_[i]) return;
    auto& out = found_.local();
    auto& close = near_.local();
    neighbours(i, close);
    const auto me = static_cast<std::uint32_t>(i);
    if (close.size() <= cap) {
      for (const auto& [d2, j] : close)
        if (j > me) out.push_back({me, j});
      return;
    }
    capped_[i] = 1;
    std::nth_element(close.begin(), close.begin() + static_cast<std::ptrdiff_t>(cap), close.end());
    for (std::size_t k = 0; k < cap; ++k) out.push_back({std::min(me, close[k].second), std::max(me, close[k].second)});
  });
  if (std::find(capped_.begin(), capped_.end(), 1) != capped_.end())
    for_each(n, [&](std::size_t i) {
      if (!enabled_[i] || capped_[i]) return;
      auto& out = found_.local();
      auto& close = near_.local();
      neighbours(i, close);
      for (const auto& [d2, j] : close)
        if (j < i && capped_[j]) out.push_back({j, static_cast<std::uint32_t>(i)});
    });
  pairs_.clear();
  for (auto& out : found_) {
    pairs_.insert(pairs_.end(), out.begin(), out.end());
    out.clear();
  }
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());  // pairs both drones reported
}

// After the move, drones closer than their radii are pushed apart along the line between them, each by
// its share of the overlap (the other's mass over both), pair by pair in sorted order as above. A pile
// of two sizes converges slower than one of one size: a light drone between heavy ones takes nearly all
// of each push, so a heavy drone's press crosses the pile in more passes, and an irregular packing
// passes pushes on less directly. After solver_passes, passes go on while the last one still found a
// pair deeper than pile_tolerance (a pile of one size rarely does, so its result is unchanged). Each
// drone's whole push is then swept against the walls from where its own move left it, so a push never
// crosses a wall however the pushes added up.
void LightWorld::separate(const StaticGeometry& geometry) {
  const double margin = slop(max_radius_) + max_radius_ / 2;  // pairs a push may bring into contact too
  find_pairs(margin);

  if (!pairs_.empty()) {
    in_pair_.assign(positions_.size(), 0);  // a flag per drone, read in id order: no sort of 2 × pairs ids
    for (const auto& [a, b] : pairs_) in_pair_[a] = in_pair_[b] = 1;
    moved_.clear();
    for (std::uint32_t i = 0; i < in_pair_.size(); ++i)
      if (in_pair_[i]) moved_.push_back(i);
    from_.resize(moved_.size());
    for (std::size_t k = 0; k < moved_.size(); ++k) from_[k] = positions_[moved_[k]];
    bool pushed = false;
    for (int pass = 0; pass < pile_passes; ++pass) {
      bool any = false;
      double deepest = 0;
      for (const auto& [a, b] : pairs_) {
        const Vec2 ab = positions_[a] - positions_[b];
        const double need = radius_[a] + radius_[b], d2 = ab.length_squared();
        if (d2 >= need * need) continue;
        const double dist = std::sqrt(d2), total = mass_[a] + mass_[b];
        deepest = std::max(deepest, (need - dist) / need);
        const Vec2 u = dist > 0 ? ab / dist : Vec2{1, 0};
        positions_[a] += u * ((need - dist) * mass_[b] / total);
        positions_[b] -= u * ((need - dist) * mass_[a] / total);
        any = true;
      }
      if (!any) break;
      pushed = true;
      if (pass + 1 >= solver_passes && deepest <= pile_tolerance) break;
    }
    if (pushed)
      for_each(moved_.size(), [&](std::size_t k) {
        const std::uint32_t i = moved_[k];
        const Vec2 push = positions_[i] - from_[k];
        if (push.is_zero()) return;
        positions_[i] = from_[k];
        Vec2 unchanged = velocities_[i];  // a push is no flight: the velocity stays
        wall_now_[i] = move(geometry, i, push, unchanged);
      });
  }

  // The pairs touching now, and those that began.
  std::vector<Pair> now;
  now.reserve(pairs_.size());
  for (const auto& [a, b] : pairs_) {
    const double touch = radius_[a] + radius_[b] + slop(std::min(radius_[a], radius_[b]));
    if (distance_squared(positions_[a], positions_[b]) < touch * touch) now.push_back({a, b});
  }
  fresh_.clear();
  std::set_difference(now.begin(), now.end(), touching_.begin(), touching_.end(), std::back_inserter(fresh_));
  touching_ = std::move(now);
}

}  // namespace salsa
