#pragma once
// One simulation: drones, targets, a map, the active behavior, contact handlers and observers, stepped
// with a fixed time step. Owns its Box2D world; no Qt.
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "salsa/behavior.hpp"
#include "salsa/contact.hpp"
#include "salsa/core/drone_config.hpp"
#include "salsa/core/static_geometry.hpp"
#include "salsa/grid.hpp"
#include "salsa/map.hpp"
#include "salsa/target.hpp"

namespace salsa {

class Simulation;
struct PhysicsWorld;  // Box2D, internal to libsalsa

/// Told about the simulation every log interval (and once at time 0). Runs on the stepping thread.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void observe(const Simulation& sim) = 0;
};

enum class SpawnMode { disc, uniform };

struct SimulationSetup {
  MapData map;
  std::optional<Vec2> spawn;          ///< overrides the map's spawn point
  SpawnMode spawn_mode = SpawnMode::disc;
  double spawn_radius = 0;            ///< m; 0: drone count × drone radius (the paper's disc)
  DroneConfig drone;
  std::size_t drones = 10;
  std::shared_ptr<Behavior> behavior;
  std::shared_ptr<TargetKind> target_kind;  ///< may be null: no targets
  std::size_t targets = 0;
  std::vector<std::shared_ptr<ContactHandler>> contact_handlers;
  double dt = 1.0 / 60;               ///< s
  int velocity_iterations = 8;
  int position_iterations = 3;
  std::uint64_t seed = 1;
  int threads = 0;                    ///< worker threads for `decide`; 0: all cores
  std::size_t log_every = 60;         ///< steps between observer calls
  /// 1: a decision takes effect one step later (as in ARGoS), so Box2D steps on one core while the
  /// drones sense and decide on the others. 0: it takes effect in the step it was made (all phases in
  /// sequence; slower on several cores).
  int decision_lag = 1;
  bool profile = false;               ///< time each phase (Simulation::profile); off saves ~12 clock reads a step
};

/// Step phases, timed separately (DESIGN §3).
enum class Phase { sense, decide, act, physics, detect, observe };
inline constexpr std::array<const char*, 6> phase_names{"sense", "decide", "act", "physics", "detect", "observe"};

struct TargetState {
  Vec2 position;
  double found_time = std::numeric_limits<double>::quiet_NaN();  ///< s; NaN until found
  std::int64_t found_by = -1;                                    ///< drone id, -1 until found
  std::uint64_t observations = 0;  ///< drone-steps during which it was in some drone's view
  bool found() const { return found_by >= 0; }
};

class Simulation final : public WorldView {
 public:
  /// Throws std::invalid_argument with a one-line reason for an unusable set-up.
  explicit Simulation(SimulationSetup setup);
  ~Simulation() override;
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  void step();
  void run_steps(std::size_t n) { for (std::size_t i = 0; i < n; ++i) step(); }

  // ---- Live changes (take effect at the next step) ----
  void set_drone_count(std::size_t n);      ///< adds drones at the spawn, or removes the highest ids
  void set_drone_config(const DroneConfig& config);  ///< rebuilds the drones where they are
  void set_behavior(std::shared_ptr<Behavior> behavior);  ///< fresh per-drone memory
  void set_map(const MapData& map, std::optional<Vec2> spawn = std::nullopt);  ///< re-spawns drones and targets
  void set_targets(std::shared_ptr<TargetKind> kind, std::size_t count);        ///< re-places targets
  void add_observer(Observer* observer) { observers_.push_back(observer); }

  // ---- State ----
  std::uint64_t step_count() const { return steps_; }
  std::size_t drone_count() const { return positions_.size(); }
  const DroneConfig& drone_config() const { return setup_.drone; }
  const SimulationSetup& setup() const { return setup_; }
  Behavior& behavior() const { return *setup_.behavior; }
  const MapData& map() const { return setup_.map; }
  Vec2 spawn_point() const { return spawn_; }
  const std::vector<TargetState>& targets() const { return targets_; }
  std::size_t targets_found() const { return found_count_; }
  std::uint64_t collisions() const { return collisions_; }  ///< contacts begun, drone–drone and drone–obstacle
  const StaticGeometry& geometry() const { return geometry_; }
  /// Nearest other drone's distance for each drone (m); +inf when alone. O(N) through the grid.
  std::vector<double> nearest_neighbour_distances() const;
  /// Seconds spent in each phase so far (zeros unless SimulationSetup::profile).
  const std::array<double, 6>& profile() const { return profile_; }

  // ---- WorldView ----
  Rect bounds() const override { return setup_.map.bounds; }
  double time() const override { return static_cast<double>(steps_) * setup_.dt; }
  double dt() const override { return setup_.dt; }
  std::span<const Vec2> drone_positions() const override { return positions_; }
  std::span<const Vec2> drone_velocities() const override { return velocities_; }
  /// The velocities the last act phase handed to Box2D (m/s), before collisions changed them.
  std::span<const Vec2> commanded_velocities() const { return commanded_; }
  bool is_free(Vec2 p, double clearance) const override { return geometry_.is_free(p, clearance); }
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const override { return geometry_.ray_cast(from, to); }

 private:
  struct Scratch;
  struct Parallel;

  // The phases of one step.
  void sense();
  void decide();
  void act();
  void physics();
  void dispatch_sightings();  // detect, part 1
  void dispatch_contacts();   // detect, part 2
  void observe();

  void build_world();
  void spawn_drones(std::size_t from, std::size_t to);
  void place_targets();
  void size_rays();
  Vec2 spawn_position(std::size_t total);
  Perception perceive(std::uint32_t id, Scratch& scratch) const;
  void read_back();
  void timed(Phase phase, const auto& fn);

  SimulationSetup setup_;
  Vec2 spawn_;
  StaticGeometry geometry_;
  std::unique_ptr<PhysicsWorld> physics_;
  std::unique_ptr<Parallel> parallel_;

  // Drones, structure of arrays indexed by id.
  std::vector<Vec2> positions_, velocities_, steering_, commanded_;
  std::vector<Rng> rngs_;
  std::vector<Vec2> ray_directions_;      ///< unit vectors of the obstacle rays
  std::vector<ObstacleHit> hits_;         ///< obstacle_rays slots per drone
  std::vector<std::uint8_t> hit_counts_;
  PointGrid drone_grid_;

  // Targets.
  std::vector<TargetState> targets_;
  PointGrid target_grid_;
  std::vector<std::vector<std::pair<std::uint32_t, double>>> seen_;  ///< per drone: (target, distance) in view
  std::size_t found_count_ = 0;
  double sensed_time_ = 0;  ///< s: when `seen_` was sensed

  std::vector<Observer*> observers_;
  Rng spawn_rng_;
  std::uint64_t steps_ = 0;
  std::uint64_t collisions_ = 0;
  std::array<double, 6> profile_{};
};

}  // namespace salsa
