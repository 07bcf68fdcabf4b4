#pragma once
// Runs tests at full speed and writes their data: per test a folder with config.json, summary.csv,
// drones.csv and targets.csv (docs/output-format.md).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "salsa/core/plugin_host.hpp"
#include "salsa/core/test_spec.hpp"

namespace salsa {

struct RunOptions {
  std::filesystem::path out = "results";
  bool force = false;   ///< replace finished tests' folders
  bool resume = false;  ///< skip tests whose folder is complete
  int threads = 0;      ///< decide threads per simulation; 0: all cores
  bool drones_csv = true;
  /// Progress: called with a line of text (test started / finished); may be empty.
  std::function<void(const std::string&)> progress;
};

struct RunResult {
  std::filesystem::path folder;
  bool skipped = false;
  double wall_seconds = 0;
  std::size_t steps = 0;
  std::size_t targets = 0, found = 0;
};

/// Before anything runs: refuses tests whose output folder exists (unless force or resume), so that
/// nothing already written is touched. Throws InputError.
void check_outputs(const std::vector<TestSpec>& tests, const RunOptions& options);

/// Runs one test into `options.out / test.name`, written in a hidden ".partial" folder first and moved
/// into place only when complete. Throws InputError / std::runtime_error.
RunResult run_test(const TestSpec& test, const PluginHost& host, const RunOptions& options);

}  // namespace salsa
