#pragma once
// Runs tests at full speed and writes their data: per test a folder with config.json, map.json,
// summary.csv, drones.csv, targets.csv and outcome.csv (docs/output-format.md).
//
// Output folders: a test writes to OUT/.<name>.partial/ and renames it to OUT/<name>/ when complete.
// Both carry a marker file (folder_marker) written before anything else, and salsa removes or replaces
// only folders that carry it: never a path computed from user text alone.
#include <atomic>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "salsa/core/csv_writer.hpp"
#include "salsa/core/plugin_host.hpp"
#include "salsa/core/test_spec.hpp"
#include "salsa/core/signals.hpp"  // install_signal_handlers, stop_signal, signal_name

namespace salsa {

/// The file that marks a folder as one salsa wrote (a test's folder or its .partial folder).
inline constexpr const char* folder_marker = ".salsa-test";

struct RunOptions {
  std::filesystem::path out = "results";
  bool force = false;   ///< replace folders salsa wrote (marked) for these tests
  bool resume = false;  ///< skip tests whose folder holds the identical finished test
  int threads = 0;      ///< decide threads per simulation; 0: all cores
  bool drones_csv = true;
  /// When set, the running test's steps so far are stored here after every step (for progress).
  std::atomic<std::size_t>* progress = nullptr;
  /// When set, called after every step (salsa bench queue records the floor's velocities here).
  std::function<void(const Simulation&)> on_step;
};

struct RunResult {
  std::filesystem::path folder;
  bool skipped = false;
  double wall_seconds = 0;      ///< set-up, stepping and writing
  double stepping_seconds = 0;  ///< the step loop alone
  std::size_t steps = 0;
  std::size_t targets = 0, found = 0;
};

/// A test failed while running (a plugin threw): one line naming the test and the plugin. The other
/// tests may go on.
struct TestFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The run was stopped by SIGINT or SIGTERM (see install_signal_handlers); the test's rows so far
/// are whole in its .partial folder. The message is one line.
struct Interrupted : std::runtime_error {
  Interrupted(const std::string& what, int sig) : std::runtime_error(what), signal(sig) {}
  int signal;
};

/// Before anything runs: refuses (InputError, one line) a bad output folder, names that fail
/// name_problem(), and tests whose folders may not be written: an existing folder without --resume
/// or --force, a finished test that differs from the one asked for (--resume, naming the first
/// difference), a folder salsa did not write (--force). Creates OUT when all is well.
void check_outputs(const std::vector<TestSpec>& tests, const PluginHost& host, const RunOptions& options);

/// What the test's config.json holds (the resolved test, a map file's path made absolute).
std::string test_config(const TestSpec& test, const PluginHost& host);

/// What a test's map.json holds: `map` (its spawn replaced by `spawn`, the point the drones started
/// around) in the map file format the json map plugin reads (docs/maps.md). Numbers are the shortest
/// text that reads back to the same double, so the json map plugin gives back the same MapData and
/// the same map gives the same bytes on every run.
std::string map_json(const MapData& map, Vec2 spawn);

/// Writes `line` to OUT/.<name>.partial/error.txt (when salsa wrote that folder): why the test
/// failed. run_test does this itself for TestFailure and WriteError.
void record_failure(const std::filesystem::path& out, const std::string& name, const std::string& line);

/// Whether `run_test` would skip this test (--resume and its folder holds the identical test).
bool already_done(const TestSpec& test, const PluginHost& host, const RunOptions& options);

/// Runs one test into `options.out / test.name`, written in a hidden ".partial" folder first and moved
/// into place only when complete, with timing.json (wall seconds and steps). Throws InputError,
/// TestFailure, WriteError or Interrupted; after TestFailure and WriteError the .partial folder holds
/// error.txt. Tests may run at once on several threads (each with its own crash note).
RunResult run_test(const TestSpec& test, const PluginHost& host, const RunOptions& options);

}  // namespace salsa
