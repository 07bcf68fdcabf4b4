#pragma once
// The sandbox's run, on a worker thread: a core Session (the same run loop as `salsa run`). The GUI never
// touches it: it posts commands, which the worker applies between steps (live changes go through
// Session::change and are recorded in its timeline), and reads the latest immutable Snapshot, which the worker publishes a few dozen times a
// second. No widgets here (tests drive it directly).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::gui {

/// What changes only when the world is rebuilt (a new test, map or target placement): the view's
/// static layer is keyed on this object's address.
struct Scene {
  MapData map;
  std::vector<Vec2> bases;    ///< each group's base (spawn point), in group order
  std::vector<Vec2> targets;  ///< target positions, by id
  double target_radius = 0;   ///< m
};

/// A uniform grid over the map bounds: how often drones were in each cell, normalised to 0–100
/// (100 = the busiest cell).
struct HeatMap {
  Vec2 origin;       ///< the bounds' min corner
  double cell = 1;   ///< m
  int cols = 0, rows = 0;
  std::vector<float> values;  ///< row-major, rows × cols, 0–100
};

/// One row of the live plots.
struct StatsRow {
  double time = 0;              ///< s
  double found_percent = 0;     ///< targets found, % of all (0 when there are none)
  double coverage_percent = 0;  ///< free map area that has been in some camera's range, %
  double mean_speed = 0;        ///< m/s
  double mean_nn_distance = 0;  ///< m, nearest other drone, averaged (NaN with one drone)
};

/// The selected drone, for the inspector.
/// One column of the drones' state (Simulation::columns()) for the inspected drone.
struct StateLine {
  std::string model;           ///< who keeps it: "drone", "fleet", "wind", ...
  std::string name, unit;      ///< as the column declares them ("energy_used", "J")
  std::vector<double> values;  ///< its `width` values (x then y for a vector)
  bool whole = false;          ///< a count, an id or a code
};

struct Inspection {
  std::uint32_t id = 0;
  std::string group;                       ///< its group's name
  Vec2 position;                           ///< m
  /// Every state column of a model that is on, in the simulation's order (a model's new column joins
  /// without a line here). A model with a test model of its name is on while that one is in use.
  std::vector<StateLine> state;
  std::vector<std::uint32_t> neighbours;   ///< flying ids within its detection range
  std::vector<ObstacleHit> hits;           ///< its obstacle rays' hits, last step
  std::string memory;                      ///< Behavior::inspect(id); empty when not exposed
  /// With the fleet model on (TestSpec::fleet, or a fail.* change made): its status as drones.csv and
  /// fleet.csv name it (flying, camera_failed, landed or failed).
  bool fleet = false;
  std::string status;
  /// With "comm": the senders of the messages it receives in the next step, by ascending id.
  std::optional<std::vector<std::uint32_t>> heard;
  /// With position noise: where the drone will perceive itself at its next decision (m).
  std::optional<Vec2> perceived;
  /// The state line named `name`, or nullptr (its model is off).
  const StateLine* line(std::string_view name) const;
};

/// A group of drones as the view draws it.
struct GroupLook {
  std::string name;
  DroneConfig drone;  ///< current configuration (radius and ranges for the view)
};

enum class RunState { paused, running, failed };

/// Immutable once published.
struct Snapshot {
  std::uint64_t step = 0;
  double time = 0;  ///< s
  double dt = 0;    ///< s, the step in use (larger than the test's when `inexact`)
  bool inexact = false;
  std::shared_ptr<const Scene> scene;
  std::vector<GroupLook> groups;       ///< in the test's order; empty before a load
  std::vector<Vec2> positions, velocities;  ///< by drone id, removed ids included
  std::vector<std::uint32_t> drone_groups;  ///< by id: index into `groups` (empty: all in the first)
  std::vector<DroneStatus> status;          ///< by id (empty: all flying)
  std::vector<std::uint8_t> camera;         ///< by id: 1 while its camera works (empty: all work)
  std::vector<std::uint8_t> found;     ///< per target: 1 once found
  std::size_t targets_found = 0;
  std::uint64_t found_version = 0;     ///< changes whenever `found` does (the static layer redraws)
  /// Trails: trail_length samples per drone, drone d's at [d × trail_length, (d + 1) × trail_length),
  /// oldest first; samples not yet taken are NaN. Snapshots share one vector until a sample is taken
  /// (every few steps): copying 100,000 drones' trails for each would cost more than the step.
  std::shared_ptr<const std::vector<Vec2>> trails;
  std::size_t trail_length = 0;
  std::shared_ptr<const HeatMap> heat;     ///< a new object when it changed
  std::shared_ptr<const std::vector<StatsRow>> stats;  ///< the run's rows so far (one per stats interval)
  std::optional<Inspection> selected;
  RunState state = RunState::paused;
  std::string error;        ///< why the run stopped (state failed): one line naming the plugin
  double speed = 0;         ///< simulated seconds per wall second, recent
  std::string test_name;    ///< the loaded test's name
  std::size_t changes_applied = 0;  ///< timeline changes applied so far (the controls refresh when it moves)
  double build_ms = 0;      ///< how long the worker took to make this snapshot (the render benchmark reports it)
  /// With "comm": the messages delivered for the next step as (receiver, sender) ids, at most
  /// max_links of them (the view draws them as lines).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> links;
  static constexpr std::size_t max_links = 100000;
  /// With wind: the wind at the next step on a grid over the map, (position m, velocity m/s).
  std::vector<std::pair<Vec2, Vec2>> wind;
  static constexpr int wind_grid = 12;  ///< samples per side

  std::uint32_t group_of(std::uint32_t id) const { return id < drone_groups.size() ? drone_groups[id] : 0; }
  DroneStatus status_of(std::uint32_t id) const { return id < status.size() ? status[id] : DroneStatus::flying; }
  bool camera_works(std::uint32_t id) const { return id >= camera.size() || camera[id] != 0; }
  /// The drone's configuration (its group's; the default one before a load).
  const DroneConfig& drone_of(std::uint32_t id) const;
};

/// How the worker paces the simulation.
struct Pacing {
  enum Mode { real_time, steps_per_frame, fastest } mode = real_time;
  int steps = 1;        ///< steps_per_frame: whole steps per frame (1/60 s of wall time)
  int dt_factor = 1;    ///< > 1: the larger time step dt × factor (fast, inexact; not recorded as a test)
};

class Engine {
 public:
  explicit Engine(std::shared_ptr<const PluginHost> host);
  explicit Engine(const PluginHost& host);  ///< not owned: it outlives the engine
  ~Engine();  ///< stops the worker
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Commands. Each returns at once; the future gives "" once applied, or the one-line reason it was
  // refused, in which case nothing changed.
  /// A new start state: builds a session for `test` (paused, time 0); the test's own timed changes are
  /// the timeline and apply as it runs, exactly as in `salsa run`.
  std::future<std::string> load(TestSpec test);
  /// Rebuilds the loaded test's start state (paused, time 0): live changes dropped, the test's own kept.
  std::future<std::string> reset();
  /// A live change (keys as in salsa/core/experiments/changes.hpp), recorded at the current time.
  std::future<std::string> set(std::string key, double value);
  void start();
  void pause();
  /// One step (exact), then paused.
  std::future<std::string> step_once();
  /// Fails (returns the reason) when dt_factor makes the step too long for the physics (check_drone).
  std::future<std::string> set_pacing(Pacing pacing);
  void select(std::optional<std::uint32_t> drone);
  /// The plugins of a rescan, used from now on (resets, loads). `rebuilt`: behaviors whose files were
  /// rebuilt: every group running one switches to the new code where it is (positions and velocities
  /// kept, parameter values kept where the new code still declares them, per-drone memory fresh).
  /// Refused for a group (its old code keeps running, and the groups after it are not tried) when the
  /// new code has no such behavior or refuses the values. After a reload, as_test is refused until the
  /// next reset.
  std::future<std::string> use_plugins(std::shared_ptr<const PluginHost> host, std::vector<std::string> rebuilt = {});
  /// The behavior each group runs, in group order (empty before a load).
  std::vector<std::string> behavior_names() const;
  /// Trail samples kept per drone (0: none) and taken every `every` steps.
  void set_trails(std::size_t length, std::size_t every);

  /// The latest snapshot (never null; an empty scene before the first load). Never waits on the worker
  /// beyond a pointer copy.
  std::shared_ptr<const Snapshot> snapshot() const;

  /// The start state plus the timeline of changes so far, `time` set to now: `salsa run` of it replays
  /// this session. Refused (std::nullopt, `why` set) after the inexact larger step was used.
  std::optional<TestSpec> as_test(std::string* why = nullptr) const;
  /// Every change, applied or still due: the test's own and the live ones, in time order.
  std::vector<Change> timeline() const;
  /// The loaded test as the live changes left it (what the controls should show); nullopt before a load.
  std::optional<TestSpec> current_test() const;

  /// Called on the worker thread with a snapshot taken exactly at every multiple of `interval` s of
  /// simulated time (for recordings whose timing does not depend on the machine); nullptr stops it.
  /// The worker waits for the callback to return.
  void on_frame(double interval, std::function<void(std::shared_ptr<const Snapshot>)> callback);

  /// Blocks until every command posted so far has been applied (tests, and before saving).
  void sync();

 private:
  struct Worker;
  std::unique_ptr<Worker> worker_;
};

}  // namespace salsa::gui
