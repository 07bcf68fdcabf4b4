#pragma once
// What a frame shows (frame_renderer.hpp draws it): an immutable Snapshot of a simulation, its Scene
// (what changes only when the world is rebuilt) and what the desktop adds to it (trails, heat map,
// live plots' rows, the inspected drone). The desktop's engine publishes them; snapshot_of builds the
// part any Simulation gives (the Python package's Session.render draws that).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "salsa/core/model/simulation.hpp"

namespace salsa::gui {

/// What changes only when the world is rebuilt (a new test, map or target placement): the view's
/// static layer is keyed on this object's address.
struct Scene {
  MapData map;
  std::vector<Vec2> bases;    ///< each group's base (spawn point), in group order
  std::vector<Vec2> targets;  ///< target positions, by id, where they started when they move (Snapshot::targets)
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
  /// Read back from a finished test (recorded_inspection): what a run does not record (obstacle hits,
  /// messages, memory) is not known rather than none.
  bool recorded = false;
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
  /// Moving targets (Simulation::targets_move): where each is now, by id, drawn over the static layer
  /// rather than in it; empty: the targets are the scene's, static.
  std::vector<Vec2> targets;
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

/// The scene of `sim` as it is now: its map, each group's base, the targets and their radius.
std::shared_ptr<const Scene> scene_of(const Simulation& sim);

/// Fills what `sim` itself shows now into `snap`: step, time, dt, the groups, the drones' positions,
/// velocities, groups, status and cameras, moving targets' positions, the wind on a grid (when `wind`: the test has wind) and the
/// messages delivered for the next step (with comm). Its scene, found targets, trails, heat map, stats and
/// selection are the caller's.
void fill_snapshot(Snapshot& snap, const Simulation& sim, bool wind);

/// Each target's found flag now (1 once found), by id.
std::vector<std::uint8_t> found_flags(const Simulation& sim);

}  // namespace salsa::gui
