#pragma once
// Internal to libsalsa: salsa's own light physics ("physics": "light"), for swarms too large for Box2D's
// single-threaded step. Drones that touch stop closing in on each other, then each flies its velocity,
// swept against the static segment grid so that no wall is ever crossed, and drones that overlap are
// pushed apart by position, each push swept against the walls too. The per-drone work (moves, the
// search for pairs) runs in parallel in the simulation's task arena; the pairs are solved serially in
// sorted order: the same bytes on any thread count (docs/architecture.md, departure 24).
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "model/physics.hpp"
#include "salsa/grid.hpp"

namespace salsa {

class LightWorld final : public Physics {
 public:
  explicit LightWorld(tbb::task_arena& arena) : arena_(arena) {}

  void add_drone(std::uint32_t id, Vec2 position, Vec2 velocity, const DroneConfig& config, bool enabled) override;
  void remove_drones_from(std::size_t n) override;
  void disable(std::uint32_t id) override;
  void set_velocities(std::span<const Vec2> velocities, std::span<const DroneStatus> status) override;
  void advance(const StaticGeometry& geometry, double dt, int velocity_iterations, int position_iterations) override;
  void read_back(std::span<Vec2> positions, std::span<Vec2> velocities) const override;
  std::span<const ContactEvent> begun() const override { return begun_; }

  /// Most passes over the pairs per step, for velocities and for positions (each stops once nothing
  /// changes: only a pile takes them all). 32 keeps a pressed pile of 400 within 1 % overlap, 16 within 4 %.
  static constexpr int solver_passes = 32;
  /// Most passes of the position solver in a pile that, after solver_passes, still overlaps more than
  /// pile_tolerance of a pair's radii sum: piles of two sizes and masses (small and large drones took
  /// about 200 to stay under 2 %, against 3–25 % at 32).
  static constexpr int pile_passes = 256;
  static constexpr double pile_tolerance = 0.01;
  /// How close counts as touching (m): a drone of radius r touches what lies within r + slop(r).
  static double slop(double radius) { return std::min(0.01, 0.1 * radius); }
  /// The most neighbours a drone keeps in a step's pairs (its nearest, ties by id): as many drones as
  /// fit, by area, within its reach (radii + margin, at most 2.6 × the largest radius) when no two
  /// centres come closer than half the smallest radius. Apart, equal drones have 6 within reach (the
  /// densest spawn about 6 on average); the cap (about 120 for one size) binds only where they overlap by
  /// three quarters of their radii's sum (a swarm pressed into a corner at the step limit reached 61),
  /// in a pile far fuller than its map, which it keeps at n × the cap pairs instead of n².
  static std::size_t neighbour_cap(double smallest, double largest) {
    const double apart = smallest / 4, reach = 2 * largest + slop(largest) + largest / 2;
    const double fit = (reach + apart) / apart;  // discs of radius `apart` around each centre, disjoint
    return static_cast<std::size_t>(fit * fit);
  }

 private:
  using Pair = std::pair<std::uint32_t, std::uint32_t>;  // drone ids, first < second
  template <class Fn>
  void for_each(std::size_t n, Fn&& fn);
  /// Moves drone `i` by `d`, sliding along the walls it meets; `v` loses its components into them.
  /// Returns whether it ends touching a wall.
  bool move(const StaticGeometry& geometry, std::uint32_t i, Vec2 d, Vec2& v);
  void stop_closing(double dt);
  void separate(const StaticGeometry& geometry);
  void find_pairs(double margin);

  tbb::task_arena& arena_;
  std::vector<Vec2> positions_, velocities_;
  std::vector<double> radius_, mass_;
  std::vector<std::uint8_t> enabled_;
  std::vector<std::uint8_t> on_wall_;  ///< touching a wall after the last step
  std::vector<Pair> touching_;         ///< drone pairs touching after the last step, sorted
  double max_radius_ = 0, min_radius_ = 0;
  PointGrid grid_;
  std::vector<Pair> pairs_;            ///< this step's pairs near enough to touch, sorted
  std::vector<std::uint8_t> in_pair_;  ///< per drone: in one of this step's pairs
  std::vector<std::uint32_t> moved_;   ///< drones in this step's pairs, ascending
  std::vector<Vec2> from_;             ///< where each of them was before the pushes
  std::vector<std::uint8_t> wall_now_; ///< touching a wall after this step
  std::vector<Pair> fresh_;            ///< pairs that began touching this step, sorted
  tbb::enumerable_thread_specific<std::vector<Pair>> found_;  ///< pairs found by each thread
  using Near = std::pair<double, std::uint32_t>;               // distance², id: nearest first, ties by id
  tbb::enumerable_thread_specific<std::vector<Near>> near_;   ///< one drone's neighbours, per thread
  std::vector<std::uint8_t> capped_;   ///< this step: the drone had more neighbours than the cap
  std::vector<ContactEvent> begun_;
  /// A pair in the velocity solver, with its direction and allowed closing speed (fixed for the step).
  struct Contact {
    Pair pair;
    Vec2 u;
    double allowed;
  };
  std::vector<Contact> contacts_;
};

}  // namespace salsa
