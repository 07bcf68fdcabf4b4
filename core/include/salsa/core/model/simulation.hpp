#pragma once
// One simulation: drones, targets, a map, the active behavior, contact handlers and observers, stepped
// with a fixed time step. Owns its physics (Box2D's, or the light one); no Qt.
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/behavior.hpp"
#include "salsa/contact.hpp"
#include "salsa/core/model/columns.hpp"
#include "salsa/core/model/comm.hpp"
#include "salsa/core/model/drone_config.hpp"
#include "salsa/core/model/drone_model.hpp"
#include "salsa/core/model/limits.hpp"
#include "salsa/core/model/static_geometry.hpp"
#include "salsa/core/model/wind.hpp"
#include "salsa/grid.hpp"
#include "salsa/map.hpp"
#include "salsa/metric.hpp"  // TargetState
#include "salsa/target.hpp"
#include "salsa/wind.hpp"

namespace salsa {

class Simulation;
class BatchBehavior;  // batch_behavior.hpp
class Physics;  // Box2D's or the light physics, internal to libsalsa

/// Told about the simulation every log interval (and once at time 0). Runs on the stepping thread.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void observe(const Simulation& sim) = 0;
};

/// A plugin threw: which one (kind and index), and its own message in what() (on one line). `kind` is
/// "behavior", "target kind", "contact handler" (index: its position in
/// SimulationSetup::contact_handlers; 0 otherwise), "map", "metric" or "wind" (the wind field). The caller, who knows the
/// registered names and files, turns this into the line the user reads (failed_plugin in session.hpp).
struct PluginFailure : std::runtime_error {
  PluginFailure(std::string kind, std::size_t index, const std::string& message);
  std::string kind;
  std::size_t index = 0;
};

enum class SpawnMode { disc, uniform };


/// One group of drones alike: its drone configuration, count, behavior and base. A test without
/// "groups" is one group named "swarm".
struct GroupSetup {
  std::string name = "swarm";
  DroneConfig drone;
  std::size_t drones = 10;
  std::shared_ptr<Behavior> behavior;
  std::optional<Vec2> spawn;          ///< the group's base; overrides the map's spawn point
  SpawnMode spawn_mode = SpawnMode::disc;
  double spawn_radius = 0;            ///< m; 0: drone count × drone radius (the paper's disc)
};

/// Random failures, each drone's own exponential clock. Its failure times come from the seed alone (a
/// stream per drone id), never from the behavior's randomness: paired across behaviors.
struct FailureSetup {
  double drone_mtbf = 0;   ///< s, mean time to failure of the whole drone; 0: never
  double camera_mtbf = 0;  ///< s, of its camera only (it flies on, seeing no targets); 0: never
  bool operator==(const FailureSetup&) const = default;
};
/// FailureSetup's fields, declared once (schema.hpp): a test's "failures", its timed changes and sweeps
/// (failures.<name>) and its tune keys follow it.
const Schema<FailureSetup>& failure_schema();

struct SimulationSetup {
  MapData map;
  std::vector<GroupSetup> groups{1};  ///< drone ids run over the groups in order
  FailureSetup failures;
  /// The air's motion (wind.hpp): constant + gusts + the field's, added to every flying drone's air
  /// velocity. All zero and no field: off, the step exactly as without wind.
  Wind wind;
  std::shared_ptr<WindField> wind_field;  ///< may be null: no field
  CommSetup comm;                     ///< messages between drones (off by default)
  /// Models with their own per-drone columns and step function (drone_model.hpp), in this order.
  std::vector<DroneModel> models;
  std::shared_ptr<TargetKind> target_kind;  ///< may be null: no targets
  std::size_t targets = 0;
  std::vector<std::shared_ptr<ContactHandler>> contact_handlers;
  double dt = 1.0 / 60;               ///< s
  int velocity_iterations = 8;
  int position_iterations = 3;
  PhysicsMode physics = PhysicsMode::box2d;
  std::uint64_t seed = 1;
  int threads = 0;                    ///< worker threads for `decide`; 0: all cores
  std::size_t log_every = 60;         ///< steps between observer calls
  /// 0 (the default, the SALSA paper's sequential definition): a decision takes effect in the step it
  /// was made from (all phases in sequence). 1: one step later (as in ARGoS), so Box2D steps on one
  /// core while the drones sense and decide on the others (faster on several cores).
  int decision_lag = 0;
  bool profile = false;               ///< time each phase (Simulation::profile); off saves ~12 clock reads a step
};

/// What the core does with a drone of a group with return_to_base on (return_to_base.cpp) instead of its
/// behavior: nothing (`none`: the behavior flies it), flying it home, charging it there, flying it back
/// out to where it left off. Its status stays DroneStatus::flying throughout.
enum class Errand : std::uint8_t { none = 0, returning = 1, charging = 2, outbound = 3 };

/// Step phases, timed separately (`salsa bench --profile`). `communicate`: the messages broadcast in
/// decide matched to their receivers (the comm model); `fleet`: batteries and failures.
enum class Phase { sense, decide, communicate, act, physics, fleet, detect, observe };
inline constexpr std::array<const char*, 8> phase_names{"sense", "decide", "communicate", "act", "physics", "fleet", "detect", "observe"};

class Simulation final : public WorldView {
 public:
  /// Throws std::invalid_argument with a one-line reason for an unusable set-up (see the checks above).
  explicit Simulation(SimulationSetup setup);
  ~Simulation() override;
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  void step();
  void run_steps(std::size_t n) { for (std::size_t i = 0; i < n; ++i) step(); }

  // ---- Live changes (take effect at the next step). Each either succeeds or throws and leaves the
  // simulation exactly as it was (the new state is built aside, then swapped in); std::invalid_argument
  // for a refused value, or what the plugin threw. Drone ids are never reused: every other drone keeps
  // its place, memory and random stream. A map or target change re-spawns everything and resets the
  // behaviors and contact handlers (before swapping in, with a view of the new state).
  /// The group's drone count: new drones (ids from drone_count() up, fresh memory) at its base, or
  /// its highest ids removed (status removed). The contact handlers are reset.
  void set_drone_count(std::size_t n, std::uint32_t group = 0);
  void set_drone_config(const DroneConfig& config, std::uint32_t group = 0);  ///< rebuilds the group's drones where they are
  void set_behavior(std::shared_ptr<Behavior> behavior, std::uint32_t group = 0);  ///< fresh per-drone memory
  void set_map(const MapData& map, std::optional<Vec2> spawn = std::nullopt);  ///< re-spawns drones and targets; spawn: the first group's base
  void set_targets(std::shared_ptr<TargetKind> kind, std::size_t count);        ///< re-places targets
  void set_failures(const FailureSetup& failures);  ///< rates from the next step on; each drone's clock runs on
  /// The wind from the next step on (`field` may be null, or the running one: wind_field_ptr()). Refused
  /// when a group could be carried through a wall (check_wind). The gusts go on from their value now.
  void set_wind(const Wind& wind, std::shared_ptr<WindField> field);
  /// The comm model from the next step on (comm_problem refused). Messages in flight keep their
  /// deliveries; a new latency drops them.
  void set_comm(const CommSetup& comm);
  /// Drone `id` fails (the whole drone, or its camera only) now; nothing when it is down already,
  /// std::invalid_argument when there is no such drone. A fraction: that share of the flying drones (rounded to the nearest), chosen with the
  /// seed's own stream, so every behavior of a repeat loses the same drones if the same fly.
  void fail(std::uint32_t id, bool camera_only = false);
  void fail_fraction(double fraction, bool camera_only = false);
  /// A new time step (s), from the next step on: the GUI's "larger time step" (fast, inexact). Refused
  /// (std::invalid_argument) when a drone could pass through a wall in one step (check_drone,
  /// check_resolution). Time goes on from where it is.
  void set_dt(double dt);
  /// The step function of the DroneModel of that name, from the next step on (its settings changed);
  /// its columns keep their values. A model the simulation lacks joins it, its columns at 0.
  void set_model(DroneModel model);
  void add_observer(Observer* observer) { observers_.push_back(observer); }

  // ---- State ----
  std::uint64_t step_count() const { return steps_; }
  std::size_t drone_count() const { return drones_.positions.size(); }  ///< ids, removed ones included
  std::size_t flying_count() const { return flying_; }
  const DroneConfig& drone_config(std::uint32_t group = 0) const { return setup_.groups[group].drone; }
  const SimulationSetup& setup() const { return setup_; }
  Behavior& behavior(std::uint32_t group = 0) const { return *setup_.groups[group].behavior; }
  const MapData& map() const override { return setup_.map; }
  Vec2 spawn_point() const { return groups_[0].base; }
  /// Per drone: whether its camera works, energy drawn so far (J), battery left (J; +inf without a
  /// battery model) and when its status began (s; 0 while flying).
  bool camera_works(std::uint32_t id) const { return drones_.fleet.camera[id] != 0; }
  double energy_used(std::uint32_t id) const { return drones_.fleet.used[id]; }
  double battery_left(std::uint32_t id) const { return drones_.fleet.charge[id]; }
  double status_time(std::uint32_t id) const { return drones_.since[id]; }
  /// Its errand (none unless its group returns to base) and the time it has charged on one (s).
  Errand errand(std::uint32_t id) const {
    return id < drones_.errands.state.size() ? static_cast<Errand>(drones_.errands.state[id]) : Errand::none;
  }
  double charging_time(std::uint32_t id) const { return id < drones_.errands.charging.size() ? drones_.errands.charging[id] : 0.0; }
  /// Each target's state, its position where it is now (targets of a kind that moves() move every step).
  const std::vector<TargetState>& targets() const { return targets_.states; }
  /// The targets move: their kind moves() and there are some.
  bool targets_move() const { return targets_.moving; }
  const Wind& wind() const { return setup_.wind; }
  const std::shared_ptr<WindField>& wind_field_ptr() const { return setup_.wind_field; }
  Vec2 gust() const { return gusts_.value(); }  ///< m/s, the gusts of the next step (the same everywhere)
  /// The wind at `p` at time `t` (m/s): constant + gusts + the field's (a plugin call: may throw
  /// PluginFailure "wind").
  Vec2 wind_at(Vec2 p, double t) const;
  /// Each drone's velocity relative to the air (m/s): drone_velocities() minus the wind it flew in
  /// (the same span as drone_velocities() while the test has had no wind).
  std::span<const Vec2> air_velocities() const { return wind_active_ ? drones_.air.velocity : drones_.velocities; }
  std::size_t targets_found() const { return targets_.found; }
  std::uint64_t collisions() const { return collisions_; }  ///< contacts begun, drone–drone and drone–obstacle
  /// False detections so far (the drone configuration's false_detection_rate): phantom targets the
  /// drones perceived, never found and never seen by a contact handler.
  std::uint64_t false_detections() const { return false_detections_; }
  /// Where drone `id` will perceive itself at the next step's decision: its position plus its
  /// position_noise draw for that step (the position itself without noise). For the desktop's
  /// inspector: true against perceived.
  Vec2 perceived_position(std::uint32_t id) const;
  /// The comm model's counters so far (all zero without "comm").
  const CommCounters& comm_counters() const { return comm_counters_; }
  /// What drone `id` receives in the next step's decide, if it flies then (empty without "comm").
  std::vector<Message> inbox(std::uint32_t id) const;
  const StaticGeometry& geometry() const { return geometry_; }
  /// Nearest other drone's distance for each drone (m); +inf when alone. About O(N) through a grid sized
  /// to the drones' spread, whatever the detection range.
  std::vector<double> nearest_neighbour_distances() const;
  /// The drone's obstacle-ray hits of the last sense phase.
  std::span<const ObstacleHit> obstacle_hits(std::uint32_t id) const {
    return {drones_.sensing.hits.data() + id * ray_slots_, id < drones_.sensing.hit_counts.size() ? drones_.sensing.hit_counts[id] : 0u};
  }
  /// The drones' state as named columns (columns.hpp), each a view of the array the step uses: a
  /// model's columns are there while the model keeps them (the wind's once the test has had wind).
  std::vector<StateColumn> columns() const;
  /// Every column a simulation may keep, whichever models a test turns on (no data): for checking a
  /// name before a run and for `salsa describe columns`.
  static std::vector<StateColumn> declared_columns();
  /// The column called `name`, or one with data == nullptr.
  StateColumn column(std::string_view name) const;
  /// Seconds spent in each phase so far (zeros unless SimulationSetup::profile).
  const std::array<double, phase_names.size()>& profile() const { return profile_; }

  // ---- WorldView ----
  Rect bounds() const override { return setup_.map.bounds; }
  double time() const override { return time_at(steps_); }
  double dt() const override { return setup_.dt; }
  std::span<const Vec2> drone_positions() const override { return drones_.positions; }
  std::span<const Vec2> drone_velocities() const override { return drones_.velocities; }
  /// The velocities the last act phase handed to Box2D (m/s), before collisions changed them.
  std::span<const Vec2> commanded_velocities() const { return drones_.commanded; }
  bool is_free(Vec2 p, double clearance) const override { return geometry_.is_free(p, clearance); }
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const override { return geometry_.ray_cast(from, to); }
  const DroneProperties& drone(std::uint32_t group = 0) const override { return groups_[group].properties; }
  std::span<const std::uint32_t> drone_groups() const override { return drones_.groups; }
  std::span<const DroneStatus> drone_status() const override { return drones_.status; }
  std::size_t group_count() const override { return groups_.size(); }
  Vec2 base(std::uint32_t group) const override { return groups_[group].base; }

 private:
  struct Scratch;
  struct Parallel;
  struct Batches;  // the gathered perceptions of the groups that decide in batches

  // The phases of one step.
  void sense();
  void decide();
  void communicate();
  void act();
  void sample_wind();         // with wind: each flying drone's, at the step's start (drones_.air.wind)
  void act_in_wind();         // act when the test has (had) wind
  void physics();
  void fleet();               // batteries and failures
  void errand_step(std::uint32_t id, bool on_base);  // fleet, for a drone of a group that returns to base
  Vec2 errand_steering(const Perception& me) const;  // decide, for a drone on an errand
  void way_home(std::uint32_t id);                    // its way home's length and next point (errands)
  bool on_errand(std::uint32_t id) const { return id < drones_.errands.state.size() && drones_.errands.state[id] != 0; }
  void dispatch_sightings();  // detect, part 1
  void dispatch_contacts();   // detect, part 2
  void move_targets();        // a kind that moves its targets: one step of theirs, after the drones' (move_targets.cpp)
  void observe();
  void run_models(ModelPhase phase);  // the DroneModels of that phase, in setup order
  void comm_changed();  // drones, sizes or the model changed: resize before the next decide, forget inbox()'s grid

  // Drones, structure of arrays indexed by id (columns(): their names and units): the drone's own
  // arrays, then each model's in a struct that declares its columns in the model's file.
  struct Drones {
    std::vector<Vec2> positions, velocities, steering, commanded;
    std::vector<Rng> rngs;
    std::vector<std::uint32_t> groups;
    std::vector<DroneStatus> status;
    std::vector<double> since;          ///< s: when the status began
    /// Batteries and failures (fleet.cpp).
    struct Fleet {
      std::vector<std::uint8_t> camera;   ///< 1 while the camera works
      std::vector<double> used, charge;   ///< J drawn so far; J left in the battery (+inf: no battery model)
      /// Failure clocks: exposure so far (∫ dt / mtbf) against an Exp(1) draw from the drone's failure
      /// stream; the drone (its camera) fails when exposure reaches the draw. Rates may change live.
      std::vector<double> exposure, due, camera_exposure, camera_due;
      void columns(std::vector<StateColumn>& out) const;
    } fleet;
    /// With wind only (act.cpp): velocity relative to the air, and the wind sampled at the step's start,
    /// perceived in its decide phase and added in its act phase (m/s).
    struct Air {
      std::vector<Vec2> velocity, wind;
      void columns(std::vector<StateColumn>& out) const;
    } air;
    /// With return to base only, sized once a group has it (return_to_base.cpp): the Errand, the time
    /// charged, the way home and the energy it needs, where its behavior left off.
    struct Errands {
      std::vector<std::uint8_t> state;
      std::vector<double> charging, need, need_way;  ///< s charged; J and m of the way home
      std::vector<Vec2> resume, next;  ///< where it left off; the point it flies at on its way home
      /// Per group: the length of the shortest free path home from each cell of a grid over the map
      /// (return_to_base.cpp), made when first needed; a map change drops it with the drones.
      struct HomeMap;
      std::vector<std::shared_ptr<const HomeMap>> home;
      void grow(std::size_t drones);
      void columns(std::vector<StateColumn>& out) const;
    } errands;
    /// What each drone's obstacle rays hit in the last sense (sense.cpp).
    struct Sensing {
      std::vector<ObstacleHit> hits;      ///< ray_slots_ per drone
      std::vector<std::uint8_t> hit_counts;
      void columns(std::vector<StateColumn>& out) const;
    } sensing;
    /// The columns of SimulationSetup::models, in their order (drone_model.cpp).
    std::vector<ModelState> models;
  };
  const Drones::Errands::HomeMap& home_map(std::uint32_t group);  // return to base's, made when first needed
  /// What the simulation derives for each group from its GroupSetup.
  struct Group {
    DroneProperties properties;  ///< its drone configuration as plugins see it
    Vec2 base;                   ///< spawn point
    std::vector<Vec2> rays;      ///< unit vectors of its obstacle rays
    double reach = 0;            ///< m: the target kind's view_range for its camera
    /// Its drone configuration's sensor noise (all 0: off, and the perception is built as without it).
    struct Noise {
      double position = 0, neighbours = 0, obstacles = 0, miss = 0, false_rate = 0;
      bool perceived() const { return position > 0 || neighbours > 0 || obstacles > 0; }  ///< perceive changes
      bool detection() const { return miss > 0 || false_rate > 0; }                       ///< sense changes
    } noise;
  };
  struct Targets {
    std::vector<TargetState> states;
    PointGrid grid;
    double cell = 1;  ///< m, the grid's cell size
    std::size_t found = 0;
    /// Moving targets only (TargetKind::moves): their positions (states' copied, for the grid and
    /// move()), velocities (move()'s state), the seed's motion stream and the farthest any target may
    /// have gone so far (m, max_speed × time: how much a drone's list of targets in reach may be off).
    bool moving = false;
    std::vector<Vec2> positions, velocities, before;
    Rng rng;
    double radius = 0, max_speed = 0, travel = 0;
  };
  struct World;  // everything a map change rebuilds

  // Set-up and live changes: each builds its new state aside (may throw), then installs it (cannot).
  static World build_world(const SimulationSetup& setup, Parallel& parallel);
  /// `from` with `count` new drones of `group` appended, spawned at its base.
  static Drones grown(Drones from, std::uint32_t group, std::size_t count, const SimulationSetup& setup,
                      const StaticGeometry& geometry, Vec2 base, Rng& spawn_rng, double time);
  static Group make_group(const GroupSetup& g, Vec2 base, const TargetKind* kind, bool with_targets);
  /// The behavior's message_size(), checked against max_message_size (a PluginFailure naming group g).
  static std::size_t message_size(const Behavior& behavior, std::uint32_t g);
  /// `kind` (may be null) tells whether they move; their motion stream is the seed's.
  static Targets make_targets(std::vector<Vec2> positions, const std::vector<Group>& groups, const TargetKind* kind, std::uint64_t seed);
  static std::size_t ray_slots(const std::vector<Group>& groups);
  /// Tells the contact handlers the drones or targets were (re)made; `world` is the state from now on.
  void reset_handlers(const WorldView& world) const;
  void install(World&& world) noexcept;
  void add_bodies();                 ///< every drone's body, in id order; disabled unless flying
  void ground(std::uint32_t id, DroneStatus status);  ///< stops a flying drone for good
  Perception perceive(std::uint32_t id, Senses senses, Scratch& scratch) const;
  /// `me` (built from the truth) as the drone's noisy sensors perceive it (Group::Noise).
  void add_noise(Perception& me, Senses senses, Scratch& scratch) const;
  /// Group g's flying drones perceived into one batch and decided by its batch behavior (decide_batch.cpp).
  void decide_batch(std::uint32_t g, BatchBehavior& behavior, Senses senses, bool noise);
  void read_back();
  /// The wind has been on at some time: from then on air velocities are kept (drones_.air).
  void track_air();  ///< starts air velocities for drones that have none yet (their velocity now)
  void timed(Phase phase, const auto& fn);
  /// The time after `steps` steps: steps × dt, counted from the last set_dt.
  double time_at(std::uint64_t steps) const { return dt_base_time_ + static_cast<double>(steps - dt_base_steps_) * setup_.dt; }

  SimulationSetup setup_;
  std::vector<Group> groups_;
  std::size_t ray_slots_ = 0;  ///< the most obstacle rays of any group
  double grid_range_ = 0;      ///< the largest detection range: the drone grid's cells are half of it
  StaticGeometry geometry_;
  std::unique_ptr<Physics> physics_;
  std::unique_ptr<Parallel> parallel_;
  std::unique_ptr<Batches> batches_;  ///< made at the first batch decide

  Drones drones_;
  std::size_t flying_ = 0;     ///< drones with status flying
  PointGrid drone_grid_;
  Targets targets_;
  /// What sense keeps per drone across steps, in one place (sense visits drones in grid order, so
  /// each drone's record is a cache miss: one, not four).
  struct Sensed {
    /// The targets in view this step (its Perception::targets but for noise) and the step before;
    /// the positions in `seen` of those that were not in view before (Sightings::on_entry).
    std::vector<TargetSeen> seen, before;
    std::vector<std::uint32_t> entered;
    /// The targets within reach + margin of `anchor`, in the target grid's order, or by id when they
    /// move (targets_in_reach); Targets::travel when it was made.
    struct Candidate {
      Vec2 at;
      std::uint32_t id;
    };
    std::vector<Candidate> near;
    Vec2 anchor;
    double reach = -1;  ///< the reach `near` was made for; -1: none
    double travel = 0;
  };
  std::vector<Sensed> sensed_;  ///< per drone; cleared: whatever is in view next comes into view
  /// Per drone: its false detections of this step, as offsets from its true position (sized only once a
  /// group has a false detection rate).
  std::vector<std::vector<Vec2>> phantoms_;

  std::vector<Observer*> observers_;
  Rng spawn_rng_;
  std::uint64_t fraction_failures_ = 0;  ///< fail_fraction calls so far: each draws from its own stream
  std::uint64_t steps_ = 0;
  std::uint64_t dt_base_steps_ = 0;  ///< step count and time at the last set_dt (0 and 0 without one)
  double dt_base_time_ = 0;
  std::uint64_t collisions_ = 0;
  std::uint64_t false_detections_ = 0;
  bool wind_active_ = false;  ///< the wind was on at some time: act and read_back keep air velocities
  Gusts gusts_;
  std::array<double, phase_names.size()> profile_{};

  // Messages (the comm model): each group's behavior's message_size, the messages in flight, counters.
  std::vector<std::size_t> message_sizes_;
  std::unique_ptr<CommState> comm_;
  bool comm_stale_ = true;  ///< sizes, drones or latency changed: comm_ is resized before the next decide
  mutable std::vector<CommState::Counts> comm_counts_;  ///< per receiver, this step: each drone's perceive writes its own
  CommCounters comm_counters_;
  double comm_reach_ = 0;  ///< this step's CommState::reach
  mutable PointGrid inbox_grid_;  ///< inbox(): the drone grid of the next step, built once per step asked
  mutable std::uint64_t inbox_grid_step_ = std::numeric_limits<std::uint64_t>::max();
};

}  // namespace salsa
