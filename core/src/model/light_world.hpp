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

 private:
  using Pair = std::pair<std::uint32_t, std::uint32_t>;  // drone ids, first < second
  template <class Fn>
  void for_each(std::size_t n, Fn&& fn);
  /// Moves drone `i` by `d`, sliding along the walls it meets; `v` loses its components into them.
  /// Returns whether it ends touching a wall.
  bool move(const StaticGeometry& geometry, std::uint32_t i, Vec2 d, Vec2& v);
  void stop_closing(double dt);
  void separate(const StaticGeometry& geometry);

  tbb::task_arena& arena_;
  std::vector<Vec2> positions_, velocities_;
  std::vector<double> radius_, mass_;
  std::vector<std::uint8_t> enabled_;
  std::vector<std::uint8_t> on_wall_;  ///< touching a wall after the last step
  std::vector<Pair> touching_;         ///< drone pairs touching after the last step, sorted
  double max_radius_ = 0;
  PointGrid grid_;
  std::vector<Pair> pairs_;            ///< this step's pairs near enough to touch, sorted
  std::vector<std::uint32_t> moved_;   ///< drones in this step's pairs, ascending
  std::vector<Vec2> from_;             ///< where each of them was before the pushes
  std::vector<std::uint8_t> wall_now_; ///< touching a wall after this step
  std::vector<Pair> fresh_;            ///< pairs that began touching this step, sorted
  tbb::enumerable_thread_specific<std::vector<Pair>> found_;  ///< pairs found by each thread
  std::vector<ContactEvent> begun_;
};

}  // namespace salsa
