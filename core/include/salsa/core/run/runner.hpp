#pragma once
// Runs tests at full speed and writes their data: per test a folder with config.json, map.json,
// summary.csv, drones.csv, targets.csv and outcome.csv (docs/output-format.md).
//
// How output folders are claimed, checked and replaced: output_folder.hpp.
#include <atomic>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "salsa/core/experiments/metric_list.hpp"  // DataColumns, data_columns
#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/run/session.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/run/signals.hpp"  // install_signal_handlers, stop_signal, signal_name

namespace salsa {

struct RunOptions {
  std::filesystem::path out = "results";
  bool force = false;   ///< replace folders salsa wrote (marked) for these tests
  bool resume = false;  ///< skip tests whose folder holds the identical finished test
  int threads = 0;      ///< decide threads per simulation; 0: all cores
  bool drones_csv = true;
  /// More columns of drones.csv: drone state columns by name (Simulation::columns(); a vector as
  /// <name>_x and <name>_y), after the usual ones. Checked with drone_columns_problem.
  std::vector<std::string> drone_columns;
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

/// The run was stopped by SIGINT or SIGTERM (see install_signal_handlers); the test's rows so far
/// are whole in its .partial folder. The message is one line.
struct Interrupted : std::runtime_error {
  Interrupted(const std::string& what, int sig) : std::runtime_error(what), signal(sig) {}
  int signal;
};

/// Why `names` cannot be drones.csv's extra columns ("" when they can): the first that is no drone
/// state column, with the names allowed.
std::string drone_columns_problem(const std::vector<std::string>& names);

/// Runs one test into `options.out / test.name`, written in a hidden ".partial" folder first and moved
/// into place only when complete, with timing.json (wall seconds and steps). Throws InputError,
/// TestFailure, WriteError or Interrupted; after TestFailure and WriteError the .partial folder holds
/// error.txt. Tests may run at once on several threads (each with its own crash note).
RunResult run_test(const TestSpec& test, const PluginHost& host, const RunOptions& options);

}  // namespace salsa
