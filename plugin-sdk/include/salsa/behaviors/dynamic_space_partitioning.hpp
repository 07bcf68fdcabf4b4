#pragma once
// Dynamic space partitioning, salsa's version: one virtual point per drone; the points repel each
// other until they spread evenly over the area (partition_points.hpp). The free ground, in square
// cells, is shared out among the points by a breadth-first flood from all of them at once (a Voronoi
// partition whose distances go around obstacles), and each drone sweeps its own region: it flies to
// the nearest cell of it that nobody has visited, and once all are visited, to the one visited
// longest ago. So the regions tile the free map and every region has a drone covering it. Only the
// group's flying drones count: their points spread, their regions tile the map, their visits count.
// The paper's version (a random walk in a disc around the point) is dynamic_space_partitioning_paper.hpp.
// Derive to change which cell of its region a drone visits next (docs/plugins.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
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
  }

  void prepare(const WorldView& world) override {
    if (points_.gather(world, *this)) next_flood_ = 0;
    if (cells_.empty() || world.bounds() != bounds_ || cell_size != built_cell_size_) build(world);
    if (points_.members().empty()) return;
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
      if (s.given_up != kNone) s = {};
      const bool stale = s.goal == kNone || cells_[s.goal].owner != me.id || cells_[s.goal].visited > s.since;
      if (stale) choose_goal(me, s);
      if (me.time > s.deadline && s.goal != kNone) s.given_up = s.goal;
      steer = seek(me, s.goal != kNone ? centre(s.goal) : points_[me.id]);
    }
    return steer + obstacle_weight * avoid_near_obstacles(me, kAvoidFade);
  }

  Senses senses() const override { return {.neighbours = false, .targets = false}; }  // obstacles only

  std::string inspect(std::uint32_t id) const override {
    if (id >= points_.size() || id >= memory().size()) return {};
    std::size_t owned = 0;
    for (const auto& c : cells_) owned += c.owner == id;
    const PartitionSweep& s = memory()[id];
    char text[160];
    if (s.goal == kNone) std::snprintf(text, sizeof text, "region: %zu cells; no goal", owned);
    else std::snprintf(text, sizeof text, "region: %zu cells; goal cell at (%.0f, %.0f), given up past t = %.0f s", owned,
                       centre(s.goal).x, centre(s.goal).y, s.deadline);
    return text;
  }

  /// The virtual points, one per drone id (m).
  const PartitionPoints& points() const { return points_; }

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

  void build(const WorldView& world) {
    bounds_ = world.bounds();
    built_cell_size_ = cell_size;
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
    for (Cell& c : cells_) c.owner = kNone;
    queue_.clear();
    for (std::uint32_t i : points_.members())
      if (Cell& c = cells_[index(points_[i])]; c.owner == kNone) c.owner = i, queue_.push_back(index(points_[i]));
    for (std::size_t head = 0; head < queue_.size(); ++head) {
      const std::uint32_t c = queue_[head];
      const int x = static_cast<int>(c % cols_), y = static_cast<int>(c / cols_);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (x + dx < 0 || x + dx >= cols_ || y + dy < 0 || y + dy >= rows_) continue;
          const auto n = static_cast<std::uint32_t>((y + dy) * cols_ + x + dx);
          if (cells_[n].free && cells_[n].owner == kNone) cells_[n].owner = cells_[c].owner, queue_.push_back(n);
        }
    }
  }

  // The free cell of the drone's region with the lowest goal_score. The region lies within reach of
  // its point; scanning that square costs about the region's size.
  void choose_goal(const Perception& me, PartitionSweep& s) const {
    const std::uint32_t home = index(points_[me.id]);
    const int reach = static_cast<int>(std::ceil(cutoff * points_.spacing() / cell_)) + 1;
    const int hx = static_cast<int>(home % cols_), hy = static_cast<int>(home / cols_);
    double best = std::numeric_limits<double>::infinity();
    s.goal = kNone;
    for (int y = std::max(0, hy - reach); y <= std::min(rows_ - 1, hy + reach); ++y)
      for (int x = std::max(0, hx - reach); x <= std::min(cols_ - 1, hx + reach); ++x) {
        const auto c = static_cast<std::uint32_t>(y * cols_ + x);
        if (cells_[c].owner != me.id || !cells_[c].free) continue;
        const double score = goal_score(me, centre(c), cells_[c].visited);
        if (score < best) best = score, s.goal = c;
      }
    s.since = me.time;
    if (s.goal != kNone) s.deadline = me.time + 2 * distance(me.position, centre(s.goal)) / me.max_speed + 10;
  }

  PartitionPoints points_;
  Rect bounds_;
  double cell_ = 0, built_cell_size_ = 0, next_flood_ = 0;
  int cols_ = 0, rows_ = 0;
  std::vector<Cell> cells_;
  std::vector<std::uint32_t> queue_;
};

}  // namespace salsa::behaviors
