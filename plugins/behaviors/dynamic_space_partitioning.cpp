// Dynamic space partitioning: one virtual point per drone; the points repel each other until they
// spread evenly over the area (spacing about sqrt(area / drones)), and each drone flies to its point
// and random-walks around it, so the area is shared out among the drones.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

struct Walk {
  double heading = 0;    // rad
  double time_left = 0;  // s until the next heading change while around the point
};

class DynamicSpacePartitioning final : public salsa::BehaviorWithMemory<Walk> {
 public:
  static salsa::Parameters declare() {
    return {
        {"point_speed", 8.0, 0.1, 100.0, "m/s", "top speed of the virtual points while they spread"},
        {"cutoff", 1.5, 0.5, 3.0, "", "points repel within this multiple of the equilibrium spacing"},
        {"arrival_fraction", 0.3, 0.01, 1.0, "",
         "within this fraction of the spacing a drone wanders around its point"},
        {"turn_interval", 3.0, 0.1, 60.0, "s", "mean time between heading changes around the point"},
        {"obstacle_avoidance_weight", 4.0, 0.0, 10.0, "", "weight of flying away from obstacle hits"},
    };
  }

  void reset(std::size_t drones) override {
    BehaviorWithMemory::reset(drones);
    points_.clear();  // re-seeded at the drones' positions by the next prepare
  }

  void prepare(const salsa::WorldView& world) override {
    const auto drones = world.drone_positions();
    if (points_.size() != drones.size()) points_.assign(drones.begin(), drones.end());
    if (points_.empty()) return;
    const salsa::Rect b = world.bounds();
    spacing_ = std::sqrt(b.area() / static_cast<double>(points_.size()));
    const double cutoff = cutoff_ * spacing_, step = point_speed_ * world.dt();
    const double margin = std::min({spacing_ / 2, b.width() / 2, b.height() / 2});
    grid_.build(points_, cutoff);
    next_.resize(points_.size());
    for (std::uint32_t i = 0; i < points_.size(); ++i) {  // from old positions only: order-independent
      const salsa::Vec2 p = points_[i];
      salsa::Vec2 push;
      grid_.query(p, cutoff, [&](std::uint32_t j, salsa::Vec2 q, double d2) {
        if (j == i) return;
        const double d = std::sqrt(d2);  // coincident points part along a fixed per-point direction
        push += (d > 0 ? (p - q) / d : salsa::Vec2::polar(1, 2.39996 * i)) * (1 - d / cutoff);
      });
      salsa::Vec2 m = p + push.clamped(1) * step;
      m = {std::clamp(m.x, b.min.x + margin, b.max.x - margin),
           std::clamp(m.y, b.min.y + margin, b.max.y - margin)};
      if (!world.is_free(m, kClearance) && world.is_free(p, kClearance)) {  // slide along obstacles, or stay
        const salsa::Vec2 along_x{m.x, p.y}, along_y{p.x, m.y};
        m = world.is_free(along_x, kClearance) ? along_x : world.is_free(along_y, kClearance) ? along_y : p;
      }
      next_[i] = m;
    }
    points_.swap(next_);
  }

  salsa::Vec2 decide(const salsa::Perception& me, Walk& w, salsa::Rng& rng) override {
    salsa::Vec2 steer;
    if (me.id < points_.size()) {
      const salsa::Vec2 point = points_[me.id];
      const double arrival = arrival_fraction_ * spacing_;
      if (salsa::distance_squared(me.position, point) > arrival * arrival) {
        steer = salsa::seek(me, point);
        w.time_left = 0;  // pick a fresh heading on arrival
      } else {
        if ((w.time_left -= me.dt) <= 0) w = {rng.angle(), rng.uniform(0.5, 1.5) * turn_interval_};
        steer = salsa::steer_towards(me, salsa::Vec2::polar(me.max_speed, w.heading));
      }
    }
    return steer + obstacle_weight_ * salsa::avoid_near_obstacles(me);
  }

  salsa::Senses senses() const override { return {.neighbours = false, .targets = false}; }  // obstacles only

 protected:
  void configure() override {
    point_speed_ = param("point_speed");
    cutoff_ = param("cutoff");
    arrival_fraction_ = param("arrival_fraction");
    turn_interval_ = param("turn_interval");
    obstacle_weight_ = param("obstacle_avoidance_weight");
  }

 private:
  static constexpr double kClearance = 3;  // m kept between a point and obstacles: a drone fits there

  double point_speed_ = 0, cutoff_ = 0, arrival_fraction_ = 0, turn_interval_ = 0, obstacle_weight_ = 0;
  double spacing_ = 0;  // m, equilibrium spacing sqrt(area / drones), set in prepare
  std::vector<salsa::Vec2> points_, next_;
  salsa::PointGrid grid_;
};

}  // namespace

SALSA_BEHAVIOR(DynamicSpacePartitioning, "dynamic_space_partitioning",
               "Shares the area out by mutually repelling virtual points, one per drone")
