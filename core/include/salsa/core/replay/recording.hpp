#pragma once
// A finished test read back for replay and export: the drones' state columns at every logged time,
// the targets and when each was found, the map and the groups, from the test's folder alone (no
// plugin is loaded, so a colleague's run opens where its plugins are not installed). The state comes
// from the trajectory archive (archive.hpp) when the folder has one, else from drones.csv.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/model/columns.hpp"
#include "salsa/map.hpp"
#include "salsa/vec2.hpp"

namespace salsa {

/// One drone state column over the whole run (a StateColumn's values at every frame).
struct RecordedColumn {
  std::string name, unit, model, meaning;  ///< as the simulation declares them (salsa describe columns)
  StateColumn::Type type = StateColumn::Type::f64;
  std::size_t width = 1;       ///< values per drone: 2 for a vector (x then y)
  /// frames × drones × width, frame-major; NaN where the drone has no value at that frame (removed, or
  /// a model's column before the model kept one).
  std::vector<double> values;
};

/// A group as the replay draws it.
struct RecordedGroup {
  std::string name;
  double radius = 1;            ///< m, the drone's
  double camera_range = 0, detection_range = 0, obstacle_range = 0;  ///< m
  Vec2 base;                    ///< where it started (its spawn point)
};

struct Recording {
  std::filesystem::path folder;  ///< the test folder read
  std::filesystem::path source;  ///< the file the drones' states came from (the archive or drones.csv)
  std::string test_name;
  std::uint64_t seed = 0;
  std::string salsa_version;     ///< the salsa that ran it
  double dt = 0, log_interval = 0, duration = 0;  ///< s
  MapData map;                   ///< from map.json (spawn: the first group's base)
  std::vector<RecordedGroup> groups;  ///< in the test's order (one, "swarm", for a single-group test)

  std::vector<double> times;     ///< s, one per frame, ascending
  std::size_t drones = 0;        ///< ids 0 … drones − 1 (the most the run ever had)
  /// The state columns, in the simulation's order: always position, velocity, group and status; with
  /// the fleet model camera_works and energy_used; then whatever else was recorded.
  std::vector<RecordedColumn> columns;

  std::vector<Vec2> targets;     ///< by target id, where each was placed
  /// s, by target id; NaN for a target never found.
  std::vector<double> found_time;
  std::vector<std::int64_t> found_by;  ///< drone id, −1 for a target never found
  double target_radius = 0;      ///< m

  std::size_t frames() const { return times.size(); }
  /// The column named `name`, or nullptr when it was not recorded.
  const RecordedColumn* column(std::string_view name) const;
  /// The last frame whose time is at most `t` (the first frame before it). O(log frames).
  std::size_t frame_at(double t) const;
  /// Drone `id`'s value `k` of `c` at `frame` (NaN where it has none).
  double at(const RecordedColumn& c, std::size_t frame, std::size_t id, std::size_t k = 0) const {
    return c.values[(frame * drones + id) * c.width + k];
  }
  Vec2 position(std::size_t frame, std::size_t id) const;
  /// The drone's status code at `frame` (DroneStatus: 0 flying, 1 landed, 2 failed, 3 removed).
  std::uint8_t status(std::size_t frame, std::size_t id) const;
  /// Targets found at or before time `t`.
  std::size_t found_by_time(double t) const;
};

/// Reads the finished test in `folder`: its archive when it has one, else drones.csv. Throws InputError
/// with one line naming the file and what is wrong (not a finished test, a column missing, a corrupt or
/// truncated archive, an archive from a newer salsa). Writes nothing.
Recording load_recording(const std::filesystem::path& folder);

}  // namespace salsa
