#pragma once
// Dynamic space partitioning, salsa's version: one virtual point per drone; the points repel each
// other until they spread evenly over the area (partition_points.hpp). The free ground, in square
// cells, is shared out among the points by a breadth-first flood from all of them at once (a Voronoi
// partition whose distances go around obstacles), and each drone sweeps its own region: it flies to
// the nearest cell of it that nobody has visited, and once all are visited, to the one visited
// longest ago. So the regions tile the free map and every region has a drone covering it. Only the
// group's flying drones count: their points spread, their regions tile the map, their visits count.
// `sharing` 0 (global): one set of points, one partition and one record of visits for the group.
// `sharing` 1 (radio): each drone broadcasts its point and where it is, every step; it moves its own
// point away from the points it heard lately, floods its own copy of the map from those, and counts the
// visits it made or heard of. With no radio (no "comm", or out of range) a drone's region is the map.
// The paper's version (a random walk in a disc around the point) is dynamic_space_partitioning_paper.hpp.
// Derive to change which cell of its region a drone visits next (docs/plugins.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "salsa/behavior.hpp"
#include "salsa/behaviors/partition_points.hpp"

namespace salsa::behaviors {

struct PartitionSweep {
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t goal = none;      // cell flown to
  double since = 0;               // s: when it was chosen (a visit after that ends it)
  double deadline = 0;            // s: past it the goal counts as unreachable
  std::uint32_t given_up = none;  // cell found unreachable, for prepare to mark visited
};

class DynamicSpacePartitioning : public BehaviorWithMemory<PartitionSweep> {
  static constexpr std::uint32_t kNone = PartitionSweep::none;

 public:
  void reset(std::size_t drones) override {
    BehaviorWithMemory::reset(drones);
    points_.clear();  // re-seeded at the drones' positions by the next prepare
    cells_.clear();
    views_.clear();
  }

  void prepare(const WorldView& world) override {
    if (points_.gather(world, *this)) next_flood_ = 0;
    if (cells_.empty() || world.bounds() != bounds_ || cell_size != built_cell_size_ || by_radio() != built_radio_) build(world);
    if (points_.members().empty()) return;
    if (by_radio()) return prepare_views(world);
    points_.spread(world, bounds_, point_speed, cutoff, cell_ / 2);
    // Visits: the cell under a member close to its centre; cells a member could not reach count too.
    const auto drones = world.drone_positions();
    const double t = world.time(), arrive2 = kArrival * kArrival * cell_ * cell_;
    for (std::uint32_t i : points_.members()) {
      const std::uint32_t c = index(drones[i]);
      if (distance_squared(drones[i], centre(c)) <= arrive2) cells_[c].visited = t;
      if (i < memory().size() && memory()[i].given_up != kNone) cells_[memory()[i].given_up].visited = t;
    }
    if (t >= next_flood_) flood(), next_flood_ = t + repartition_interval;
  }

  Vec2 decide(const Perception& me, PartitionSweep& s, Rng&) override {
    Vec2 steer;
    if (points_.is_member(me.id)) {
      if (by_radio()) hear(me);  // only this drone's view and cells are written: decide may run in parallel
      const std::vector<Cell>& cells = cells_of(me.id);
      if (s.given_up != kNone) s = {};
      const bool stale = s.goal == kNone || cells[s.goal].owner != me.id || cells[s.goal].visited > s.since;
      if (stale) choose_goal(me, s);
      if (me.time > s.deadline && s.goal != kNone) s.given_up = s.goal;
      steer = seek(me, s.goal != kNone ? centre(s.goal) : point_of(me.id));
    }
    return steer + obstacle_weight * avoid_near_obstacles(me, kAvoidFade);
  }

  Senses senses() const override { return {.neighbours = false, .targets = false}; }  // obstacles only

  std::string inspect(std::uint32_t id) const override {
    if (id >= points_.size() || id >= memory().size() || (by_radio() && (id >= views_.size() || views_[id].cells.empty()))) return {};
    std::size_t owned = 0;
    for (const auto& c : cells_of(id)) owned += c.owner == id;
    const PartitionSweep& s = memory()[id];
    char text[160];
    if (s.goal == kNone) std::snprintf(text, sizeof text, "region: %zu cells; no goal", owned);
    else std::snprintf(text, sizeof text, "region: %zu cells; goal cell at (%.0f, %.0f), given up past t = %.0f s", owned,
                       centre(s.goal).x, centre(s.goal).y, s.deadline);
    return text;
  }

  /// The virtual points, one per drone id (m), with `sharing` 0.
  const PartitionPoints& points() const { return points_; }
  /// Drone `id`'s view of the points with `sharing` 1 (empty before its first step).
  const HeardPoints& heard_points(std::uint32_t id) const { return views_.at(id).points; }

  SharedState shared_state() const override { return by_radio() ? SharedState::radio : SharedState::global; }
  std::size_t message_size() const override { return 4; }  // its point x, y; where it is x, y (sharing 1)

 protected:
  /// Which free cell of its region a drone flies to next: the one with the lowest score. `visited` is
  /// the time of the cell's last visit (s), negative if never. Salsa's: never-visited cells first,
  /// nearest first; then the one visited longest ago.
  virtual double goal_score(const Perception& me, Vec2 cell_centre, double visited) const {
    return visited < 0 ? distance(me.position, cell_centre) - 1e9 : visited;
  }

  Param point_speed{this, "point_speed", 8.0, 0.1, 100.0, "m/s", "top speed of the virtual points while they spread"};
  Param cutoff{this, "cutoff", 1.5, 0.5, 3.0, "", "points repel within this multiple of the equilibrium spacing"};
  Param cell_size{this, "cell_size", 20.0, 1.0, 1000.0, "m",
                  "side of a coverage cell; a drone at its centre sees all of it up to camera range × 1.41"};
  Param repartition_interval{this, "repartition_interval", 1.0, 0.0, 60.0, "s", "time between re-floods of the regions (0: every step)"};
  Param obstacle_weight{this, "obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"};
  Param sharing{this, "sharing", 0, 0, 1, "",
                "0: one partition for the group (global, the paper's); 1: each drone's own, from the points and visits its radio heard", 1};
  Param forget_after{this, "forget_after", 60.0, 0.1, 600.0, "s", "with sharing 1: a point not heard for this long is dropped from a drone's view"};

  bool by_radio() const { return sharing.value() == 1; }

 private:
  struct Cell {
    double visited = -1;          // s, last visit; -1: never
    std::uint32_t owner = kNone;  // point (= drone) whose region it is; kNone: blocked or unreachable
    bool free = false;            // centre clear of obstacles by kClearance
  };
  static constexpr double kClearance = 5;     // m between a cell's centre and obstacles for it to be a goal
  static constexpr double kArrival = 0.4;     // a drone within this fraction of a cell of its centre visits it
  static constexpr double kAvoidFade = 0.25;  // obstacle avoidance starts at a quarter of obstacle range
  static constexpr double kMaxCells = 1 << 22;

  /// A drone's own partition (sharing 1): its view of the points, its copy of the cells.
  struct View {
    HeardPoints points;
    std::vector<Cell> cells;  // made from cells_ (the free ground) on the drone's first step
  };

  const std::vector<Cell>& cells_of(std::uint32_t id) const { return by_radio() ? views_[id].cells : cells_; }
  Vec2 point_of(std::uint32_t id) const { return by_radio() ? views_[id].points.own() : points_[id]; }

  // Sharing 1, once a step: each member's own point moves from its view, its own visit counts in its
  // own cells, and every repartition_interval its cells are flooded from the points it knows.
  void prepare_views(const WorldView& world) {
    const auto drones = world.drone_positions();
    if (views_.size() < drones.size()) views_.resize(drones.size());
    const double t = world.time(), arrive2 = kArrival * kArrival * cell_ * cell_;
    const bool flood_now = t >= next_flood_;
    for (std::uint32_t i : points_.members()) {
      View& v = views_[i];
      if (!v.points.seeded()) v.points.seed(drones[i]);
      if (v.cells.empty()) v.cells = cells_;
      v.points.refresh(i, t, forget_after, bounds_.area());
      v.points.spread(i, world, bounds_, point_speed, cutoff, cell_ / 2);
      const std::uint32_t c = index(drones[i]);
      if (distance_squared(drones[i], centre(c)) <= arrive2) v.cells[c].visited = t;
      if (i < memory().size() && memory()[i].given_up != kNone) v.cells[memory()[i].given_up].visited = t;
      if (flood_now) flood(v.cells, v.points.known());
    }
    if (flood_now) next_flood_ = t + repartition_interval;
  }

  // Sharing 1, in decide: the points and visits heard, into this drone's view; then its own broadcast.
  void hear(const Perception& me) {
    View& v = views_[me.id];
    const double arrive2 = kArrival * kArrival * cell_ * cell_;
    for (const Message& m : me.messages) {
      if (m.group != group() || m.payload.size() != 4) continue;
      v.points.hear(m.sender, {m.payload[0], m.payload[1]}, m.time);
      const Vec2 at{m.payload[2], m.payload[3]};
      const std::uint32_t c = index(at);
      if (distance_squared(at, centre(c)) <= arrive2) v.cells[c].visited = std::max(v.cells[c].visited, m.time);
    }
    const Vec2 p = v.points.own();
    const double message[4] = {p.x, p.y, me.position.x, me.position.y};
    me.broadcast(message);
  }

  void build(const WorldView& world) {
    bounds_ = world.bounds();
    built_cell_size_ = cell_size;
    built_radio_ = by_radio();
    views_.clear();
    // At most kMaxCells cells, however thin the map (its long side bounds the count too).
    cell_ = std::max({cell_size.value(), std::sqrt(bounds_.area() / kMaxCells), std::max(bounds_.width(), bounds_.height()) / kMaxCells});
    cols_ = std::max(1, static_cast<int>(std::ceil(bounds_.width() / cell_)));
    rows_ = std::max(1, static_cast<int>(std::ceil(bounds_.height() / cell_)));
    cells_.assign(static_cast<std::size_t>(cols_) * rows_, Cell{});
    for (std::uint32_t c = 0; c < cells_.size(); ++c) cells_[c].free = world.is_free(centre(c), kClearance);
    next_flood_ = 0;
  }
  std::uint32_t index(Vec2 p) const {
    const int x = std::clamp(static_cast<int>((p.x - bounds_.min.x) / cell_), 0, cols_ - 1);
    const int y = std::clamp(static_cast<int>((p.y - bounds_.min.y) / cell_), 0, rows_ - 1);
    return static_cast<std::uint32_t>(y * cols_ + x);
  }
  Vec2 centre(std::uint32_t c) const {  // inside the bounds even for a clipped last column or row
    const double x = bounds_.min.x + (c % cols_ + 0.5) * cell_, y = bounds_.min.y + (c / cols_ + 0.5) * cell_;
    return {std::min(x, bounds_.max.x - cell_ / 4), std::min(y, bounds_.max.y - cell_ / 4)};
  }

  // Regions: a breadth-first flood over free cells (8 neighbours) from every member's point at once,
  // in id order, so each free cell goes to the point fewest cell steps away around obstacles. O(cells).
  void flood() {
    seeds_.clear();
    for (std::uint32_t i : points_.members()) seeds_.emplace_back(i, points_[i]);
    flood(cells_, seeds_);
  }
  void flood(std::vector<Cell>& cells, std::span<const std::pair<std::uint32_t, Vec2>> seeds) {
    for (Cell& c : cells) c.owner = kNone;
    queue_.clear();
    for (const auto& [i, p] : seeds)
      if (Cell& c = cells[index(p)]; c.owner == kNone) c.owner = i, queue_.push_back(index(p));
    for (std::size_t head = 0; head < queue_.size(); ++head) {
      const std::uint32_t c = queue_[head];
      const int x = static_cast<int>(c % cols_), y = static_cast<int>(c / cols_);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (x + dx < 0 || x + dx >= cols_ || y + dy < 0 || y + dy >= rows_) continue;
          const auto n = static_cast<std::uint32_t>((y + dy) * cols_ + x + dx);
          if (cells[n].free && cells[n].owner == kNone) cells[n].owner = cells[c].owner, queue_.push_back(n);
        }
    }
  }

  // The free cell of the drone's region with the lowest goal_score. The region lies within reach of
  // its point; scanning that square costs about the region's size.
  void choose_goal(const Perception& me, PartitionSweep& s) const {
    const std::vector<Cell>& cells = cells_of(me.id);  // the group's, or this drone's own
    const std::uint32_t home = index(point_of(me.id));
    // A drone's own partition is of the points it knows, not evenly spread: its region may reach farther.
    const int reach = by_radio() ? std::max(cols_, rows_) : static_cast<int>(std::ceil(cutoff * points_.spacing() / cell_)) + 1;
    const int hx = static_cast<int>(home % cols_), hy = static_cast<int>(home / cols_);
    double best = std::numeric_limits<double>::infinity();
    s.goal = kNone;
    for (int y = std::max(0, hy - reach); y <= std::min(rows_ - 1, hy + reach); ++y)
      for (int x = std::max(0, hx - reach); x <= std::min(cols_ - 1, hx + reach); ++x) {
        const auto c = static_cast<std::uint32_t>(y * cols_ + x);
        if (cells[c].owner != me.id || !cells[c].free) continue;
        const double score = goal_score(me, centre(c), cells[c].visited);
        if (score < best) best = score, s.goal = c;
      }
    s.since = me.time;
    if (s.goal != kNone) s.deadline = me.time + 2 * distance(me.position, centre(s.goal)) / me.max_speed + 10;
  }

  PartitionPoints points_;
  Rect bounds_;
  double cell_ = 0, built_cell_size_ = 0, next_flood_ = 0;
  bool built_radio_ = false;
  int cols_ = 0, rows_ = 0;
  std::vector<Cell> cells_;
  std::vector<std::uint32_t> queue_;
  std::vector<std::pair<std::uint32_t, Vec2>> seeds_;
  std::vector<View> views_;  // by drone id (sharing 1)
};

}  // namespace salsa::behaviors
