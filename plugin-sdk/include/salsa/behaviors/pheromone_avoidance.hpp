#pragma once
// Pheromone avoidance: drones mark the ground they fly over in a field that evaporates, and steer
// towards the least-marked direction ahead, so the swarm spreads over ground nobody visited lately.
// `sharing` 0 (global, the paper's "shared list"): one field shared by the group's flying drones.
// `sharing` 1 (messages): each drone keeps its own field, marks its own ground in it and broadcasts
// where it is; what the test's comm model delivers is marked in the receiver's field, so the swarm
// knows only what its radios carried. Derive to change the evaporation (docs/plugins.md).
#include <algorithm>
#include <cmath>
#include <vector>

#include "salsa/behavior.hpp"

namespace salsa::behaviors {

class PheromoneAvoidance : public Behavior {
 public:
  void prepare(const WorldView& world) override {
    const bool own = by_messages();
    if (!built_ || world.bounds() != bounds_ || cell_size != built_cell_size_ || own != built_own_) build(world.bounds(), own);
    const double t = world.time();
    const auto positions = world.drone_positions();
    for (std::uint32_t i = 0; i < positions.size(); ++i) {  // O(drones): cells evaporate lazily, never swept
      if (!is_member(world, *this, i)) continue;
      if (own && i >= fields_.size()) fields_.resize(positions.size());
      mark(field(i), positions[i], t);
    }
  }

  Vec2 decide(const Perception& me, Rng& rng) override {
    if (by_messages()) {  // only this drone's field is written: decide may run in parallel
      std::vector<Cell>& mine = field(me.id);
      for (const Message& m : me.messages)
        if (m.group == group() && m.payload.size() == 2) mark(mine, {m.payload[0], m.payload[1]}, m.time);
      const double where[2] = {me.position.x, me.position.y};
      me.broadcast(where);
    }
    const std::vector<Cell>& cells = field(me.id);
    const Vec2 heading = me.velocity.is_zero() ? Vec2::polar(1, rng.angle()) : me.velocity.normalized();
    double best_score = 0;
    Vec2 best;
    for (std::size_t k = 0; k < turns_.size(); ++k) {
      const Vec2 dir{heading.x * turns_[k].x - heading.y * turns_[k].y,
                     heading.x * turns_[k].y + heading.y * turns_[k].x};  // heading rotated by turn k
      // Sample short of any obstacle that direction (the ground beyond is out of reach); a direction
      // blocked right ahead, or leading out of the area, counts as maximally marked.
      double reach = look_ahead;
      for (const auto& h : me.obstacles)
        if (dir.dot(h.point - me.position) > cone_ * h.distance) reach = std::min(reach, h.distance - margin_);
      const Vec2 ahead = me.position + dir * reach;
      // Log scale: fresh ground beats marked ground clearly, but among marked directions the turn cost
      // wins, so drones cross trodden ground in straight lines instead of circling in it.
      double score = reach >= margin_ && bounds_.contains(ahead) ? std::log1p(marks(cells, ahead, me.time) / deposit) : kBlocked;
      score += turn_cost * (1 - turns_[k].x) + rng.uniform(0, 0.1);  // jitter breaks symmetric ties
      if (k == 0 || score < best_score) best_score = score, best = dir;
    }
    return steer_along(me, best) + obstacle_weight * avoid_near_obstacles(me);
  }

  Senses senses() const override { return {.neighbours = false, .targets = false}; }  // obstacles only
  void reset(std::size_t) override { built_ = false; }  // a fresh run starts with clean fields
  void resize(std::size_t) override {}                  // fields outlive drones that come and go
  std::size_t message_size() const override { return 2; }  // where the sender marked: x, y (sharing 1)
  SharedState shared_state() const override { return by_messages() ? SharedState::radio : SharedState::global; }

 protected:
  /// What is left after `elapsed` s of `value` pheromone: exponential decay at evaporation_rate.
  /// Cells are brought up to date lazily, so an override must compose: evaporate(evaporate(v, a), b)
  /// equals evaporate(v, a + b) (exponential decay does, and so does a constant-rate loss to zero).
  virtual double evaporate(double value, double elapsed) const {
    return evaporation_rate > 0 ? value * std::exp(-evaporation_rate * elapsed) : value;
  }

  void configure() override {  // what decide derives from the parameters; an override calls this one
    margin_ = look_ahead / 3;
    const auto n = static_cast<int>(directions);
    turns_.clear();  // (cos, sin) of each sampled turn, so decide needs no trigonometry
    for (int k = 0; k < n; ++k) turns_.push_back(Vec2::polar(1, 2 * pi * k / n));
    cone_ = std::cos(2 * pi / n);  // a hit within one sector of a direction blocks it
  }

  Param cell_size{this, "cell_size", 10.0, 1.0, 1000.0, "m", "side of one cell of the pheromone field"};
  Param deposit{this, "deposit", 1.0, 0.001, 1000.0, "", "pheromone a drone adds to its cell each step"};
  Param evaporation_rate{this, "evaporation_rate", 0.01, 0.0, 10.0, "1/s", "exponential decay rate of the pheromone"};
  Param look_ahead{this, "look_ahead", 30.0, 1.0, 1000.0, "m", "how far ahead the field is sampled"};
  Param directions{this, "directions", 8, 3, 64, "", "directions sampled around the current heading", 1};
  Param turn_cost{this, "turn_cost", 2.0, 0.0, 20.0, "",
                  "penalty of a 90 degree turn against log(1 + marks / deposit): higher flies straighter"};
  Param obstacle_weight{this, "obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"};
  Param sharing{this, "sharing", 0, 0, 1, "",
                "0: one field shared by the group (global, the paper's); 1: each drone's own, merged from the messages the comm model delivers", 1};

  bool by_messages() const { return sharing.value() == 1; }

 private:
  struct Cell {
    double value = 0;  // pheromone at `time`
    double time = 0;   // s, when `value` was last brought up to date
  };
  static constexpr double kBlocked = 1e9;
  static constexpr double kMaxCells = 1 << 22;         // 64 MiB at most; huge maps get coarser cells
  static constexpr double kMaxCellsPerDrone = 1 << 18;  // 4 MiB per drone's own field (sharing 1)

  void build(const Rect& b, bool own) {
    bounds_ = b;
    built_cell_size_ = cell_size;
    built_own_ = own;
    built_ = true;
    // At most ~`most` cells, however thin the map (its long side bounds the count too).
    const double most = own ? kMaxCellsPerDrone : kMaxCells;
    cell_ = std::max({cell_size.value(), std::sqrt(b.area() / most), std::max(b.width(), b.height()) / most});
    cols_ = static_cast<int>(std::ceil(b.width() / cell_)) + 1;
    rows_ = static_cast<int>(std::ceil(b.height() / cell_)) + 1;
    cells_.assign(own ? 0 : static_cast<std::size_t>(cols_) * rows_, Cell{});
    fields_.clear();  // own fields are made on a drone's first mark, so non-members cost nothing
  }
  /// The field drone `id` reads and marks: the group's, or its own (made on first use).
  std::vector<Cell>& field(std::uint32_t id) {
    if (!built_own_) return cells_;
    std::vector<Cell>& f = fields_[id];
    if (f.empty()) f.assign(static_cast<std::size_t>(cols_) * rows_, Cell{});
    return f;
  }
  /// `deposit` pheromone at p at time t. A mark older than the cell's last update (a late message) is
  /// added as what is left of it now, so marks compose whatever order they arrive in.
  void mark(std::vector<Cell>& cells, Vec2 p, double t) {
    Cell& c = cells[index(p)];
    if (t >= c.time) {
      c.value = evaporate(c.value, t - c.time) + deposit;
      c.time = t;
    } else {
      c.value += evaporate(deposit, c.time - t);
    }
  }
  std::size_t index(Vec2 p) const {
    const int x = std::clamp(static_cast<int>((p.x - bounds_.min.x) / cell_), 0, cols_ - 1);
    const int y = std::clamp(static_cast<int>((p.y - bounds_.min.y) / cell_), 0, rows_ - 1);
    return static_cast<std::size_t>(y) * cols_ + x;
  }
  double marks(const std::vector<Cell>& cells, Vec2 p, double t) const {
    const Cell& c = cells[index(p)];
    return c.value > 0 ? evaporate(c.value, t - c.time) : 0.0;
  }

  double margin_ = 10, cone_ = 0;
  std::vector<Vec2> turns_;
  Rect bounds_;
  double cell_ = 10, built_cell_size_ = 0;
  bool built_ = false, built_own_ = false;
  int cols_ = 0, rows_ = 0;
  std::vector<Cell> cells_;                ///< the group's field (sharing 0)
  std::vector<std::vector<Cell>> fields_;  ///< each drone's own, by id (sharing 1)
};

}  // namespace salsa::behaviors
