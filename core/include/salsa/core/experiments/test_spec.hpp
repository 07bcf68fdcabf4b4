#pragma once
// A test: everything one run needs, resolved (defaults filled in, names checked against the loaded
// plugins, parameters validated). Read from and written to JSON; see docs/test-format.md.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/files/input_error.hpp"
#include "salsa/core/model/drone_config.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/model/simulation.hpp"

namespace salsa {

struct PluginChoice {
  std::string name;
  ParameterValues params;  ///< every declared parameter, defaults filled in
  std::string label = {};  ///< a behavior's: the file's short name for its variant ("": its parameters say it)
  bool operator==(const PluginChoice&) const = default;
};

/// The most drones a test may hold: each group's "drones", and their sum over the groups at any time.
inline constexpr std::size_t max_test_drones = 1'000'000;

/// One group of drones alike (SimulationSetup's GroupSetup, as the test file holds it).
struct GroupSpec {
  std::string name = "swarm";       ///< the single form's one group is "swarm"
  PluginChoice behavior;
  DroneConfig drone;
  std::size_t drones = 10;
  std::optional<Vec2> spawn;        ///< the group's base; overrides the map's spawn point
  SpawnMode spawn_mode = SpawnMode::disc;
  double spawn_radius = 0;          ///< m; 0: drones × drone radius
  bool operator==(const GroupSpec&) const = default;
};

/// The largest seed anywhere (test, queue and tune files, the CLI, the desktop): 2^53, the largest
/// whole number a JSON number holds exactly.
inline constexpr std::uint64_t max_seed = 9007199254740992ULL;

struct TestSpec {
  std::string source;               ///< where it was read from, for messages ("queue.json: tests[2]")
  std::string name;                 ///< also its output folder's name
  std::vector<GroupSpec> groups{1}; ///< at least one; drone ids run over them in order
  bool named_groups = false;        ///< read from "groups" (and written back so); false: the single form
  FailureSetup failures;
  Wind wind;                        ///< "wind" without its field (salsa/core/model/wind.hpp)
  PluginChoice wind_field;          ///< "wind.field": a `wind` plugin; name empty: none
  /// Whether the test has wind (config.json then writes "wind"); off, the run is exactly as without it.
  bool has_wind() const { return wind != Wind{} || !wind_field.name.empty(); }
  CommSetup comm;                   ///< "comm": messages between drones; off without it
  /// The numbers of models declared outside the core (add_test_model, test_models.hpp), by "<key>.<field>".
  std::map<std::string, double> extra_numbers;
  PluginChoice map;
  std::string map_file;             ///< for file-based maps; absolute or relative to the working folder
  PluginChoice target;
  std::size_t targets = 0;
  /// Called in this order. Parameters not given (a TestSpec made in code) get their declared defaults.
  std::vector<PluginChoice> contact_handlers{{"detect_targets", {}}};
  std::vector<PluginChoice> metrics;  ///< in column order; a test without "metrics" gets default_metrics
  double time = 60;                 ///< s simulated
  double dt = 1.0 / 60;             ///< s
  double log_interval = 1;          ///< s between logged rows
  int velocity_iterations = 8;
  int position_iterations = 3;
  int decision_lag = 0;             ///< steps until a decision takes effect (SimulationSetup): 0 everywhere by default
  PhysicsMode physics = PhysicsMode::box2d;  ///< "physics": config.json writes it only when light
  std::uint64_t seed = 1;           ///< in [0, max_seed]
  bool seed_given = false;          ///< "seed" was in the file: it wins over the paired seed (queue.hpp)
  std::size_t repeat = 0;           ///< which repeat of its configuration in a queue (0 first)
  std::vector<Change> changes;      ///< timed live changes, in time order (salsa/core/experiments/changes.hpp)
  /// The queue's condition the test belongs to (docs/test-format.md, "Conditions"): its name and what it
  /// changes from the queue's base in words ("drones → 14 at 200 s"). Labels for the summary and the
  /// plots: the run never reads them. Empty: none (config.json then has no "condition").
  std::string condition, condition_label;
  /// "archive": also write the trajectory archive, trajectories.nc (salsa/core/replay/archive.hpp). An
  /// output choice, like drones.csv: not in config.json, the seed or what makes two tests the same.
  bool archive = false;

  std::size_t steps() const;
  std::size_t log_every() const;
  std::size_t drone_total() const;  ///< over all groups
  /// The index of the group called `name`, or -1.
  int group_index(std::string_view name) const;
  /// Whether the outputs carry the fleet's columns and fleet.csv (docs/output-format.md): the test has
  /// two or more groups, a battery, failure rates or failure events. Off, every data file is as before
  /// them (one group in "groups" is the single form, with the same seed and bytes).
  bool fleet() const;
  /// Whether a group returns to base (drone.return_to_base 1, from the start or by a timed change): the
  /// fleet's outputs then carry the time spent charging.
  bool return_to_base() const;
  bool operator==(const TestSpec&) const = default;
};

/// The first test that is the same as an earlier one, as (earlier, later) indices: equal in all but
/// name and source (what gives the same data), or nullopt. Hashes every field it compares and compares
/// in full only tests of one hash, so the time grows linearly: 10^6 tests take a fraction of a second
/// (no config text per test), whatever the queue varies.
std::optional<std::pair<std::size_t, std::size_t>> first_same_test(const std::vector<const TestSpec*>& tests);

/// The metrics a test gets when it names none (those of them the host has loaded).
inline constexpr const char* default_metrics[] = {"area_coverage", "time_to_found", "distance_flown", "collisions"};

/// Reads a test or queue file with the default QueueOptions: load_queue(file, host, {}).tests (queue.hpp).
std::vector<TestSpec> load_tests(const std::filesystem::path& file, const PluginHost& host);
/// Parses one test from JSON text (`where` names it in errors, e.g. "file.json: tests[2]"). Without a
/// "seed" it gets the paired seed of queue seed 1 and its "repeat" (default 0).
TestSpec parse_test(const std::string& json_text, const std::string& where, const PluginHost& host,
                    const std::filesystem::path& base_dir = {});

/// The fully resolved test as JSON (what config.json holds): enough to rerun it exactly, plus the
/// salsa and plugin versions.
std::string resolved_json(const TestSpec& test, const PluginHost& host);

/// A live simulation set up for `test`, its plugins created through `host`. Throws InputError for bad
/// input, the plugins' data included (the map, the targets' radius and positions: each named with its
/// plugin and file), and for what the physics cannot do faithfully (check_drone, check_resolution).
SimulationSetup make_setup(const TestSpec& test, const PluginHost& host, int threads = 0);

/// A one-line warning when `test` will likely take more than an hour of wall time ("flock.json: 1,000,000
/// drones with detection range 50 m on a 2000 m × 2000 m map: ~1,963 neighbours per drone, about 1.2e+11
/// drone-neighbour checks per simulated second; 60 s simulated: expect hours (about 21 h on one core)"),
/// else "". Estimated from the drones, their neighbours (density × π·range² over the free area, at most
/// all other drones) and the steps. `setup` is make_setup's result for `test` (it holds the map); the
/// CLI prints the line as a warning before running.
std::string workload_warning(const TestSpec& test, const SimulationSetup& setup);

/// Whether a JSON file is a map file (an object with "bounds", or with obstacles, hollow outlines or
/// lines and no "behavior" or "tests") rather than a test file.
bool is_map_file(const std::filesystem::path& file);
/// Reads a map file through the "json" map plugin and checks its spawn point. Throws InputError.
MapData load_map_file(const std::filesystem::path& file, const PluginHost& host, double drone_radius = 1);

/// The library's version, e.g. "0.1.0".
const char* salsa_version();

}  // namespace salsa
