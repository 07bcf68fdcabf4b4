#pragma once
// The benchmark suite (docs/suite.md): a versioned set of frozen tasks, each run under the suite's
// conditions on its paired seeds, and the committed results of the reference behaviors.
// suite.cpp reads the suite file and runs it; suite_report.cpp turns results into the references file
// and the report that places a behavior among the references.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace salsa::cli {

struct SuiteTask {
  std::string name;            ///< a folder name: OUT/<name>/ holds its queue's results
  std::filesystem::path file;  ///< an ordinary test file; the suite replaces its behavior
  std::string metric;          ///< the summary.csv column that scores the task
  bool higher_better = true;
};

struct Suite {
  std::filesystem::path file;     ///< suite.json
  std::uint64_t version = 0;
  std::uint64_t seed = 1;         ///< the queue seed of every task: the paired worlds
  std::uint64_t repeats = 5;
  nlohmann::ordered_json references;  ///< the reference behaviors, as sweep.behaviors lists them
  nlohmann::ordered_json conditions;  ///< as a queue's "conditions"
  std::vector<SuiteTask> tasks;
  std::filesystem::path results;  ///< the committed references file (per-seed values)
};

/// Reads and checks suite.json (every field, the task files exist). Throws InputError (one line).
Suite read_suite(const std::filesystem::path& file);

/// One scored test: a behavior's value on one task, condition and world.
struct SuiteValue {
  std::string task, condition, variant;
  std::uint64_t repeat = 0;
  std::string seed;
  std::string value;  ///< as summary.csv writes it ("" when the test failed or has no value)
};

/// The scored tests of a task's queue folder (OUT/summary.csv): every test, ok or not.
std::vector<SuiteValue> task_values(const std::filesystem::path& folder, const SuiteTask& task);

/// The references file: a header and one row per value, in the order given.
void write_references(const Suite& suite, const std::vector<SuiteValue>& values, const std::filesystem::path& file);
/// Reads a references file written by write_references; InputError when it is not this suite's.
std::vector<SuiteValue> read_references(const Suite& suite, const std::filesystem::path& file);
/// The references' means and 95 % intervals, a table per task (references.md beside the file).
void write_reference_table(const Suite& suite, const std::vector<SuiteValue>& values, const std::filesystem::path& file);

/// OUT/report.csv, OUT/report.md and OUT/plots/suite_<task>.png: `behavior` (a variant label) against
/// every reference variant, paired by repeat and seed, per task and condition: the difference, its 95 %
/// interval, the share of worlds where it did better, and its rank among them. `note` heads report.md.
void write_report(const Suite& suite, const std::string& behavior, const std::vector<SuiteValue>& values,
                  const std::filesystem::path& out, const std::string& note);

}  // namespace salsa::cli
