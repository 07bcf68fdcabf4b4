#pragma once
// A tune file (docs/tuning.md): the base test, the parameters to tune as sweep.set's dotted keys with
// their ranges, the objectives, the algorithm, the budget, the worlds and racing. Read strictly and
// checked in full before anything runs: every problem is one line naming the file, the field, the
// value and what is allowed (InputError, exit 2).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/plugins/plugin_host.hpp"

namespace salsa {

/// One tuned number: where it is in the test and the range searched.
struct TuneParameter {
  std::string key;      ///< a dotted key as sweep.set takes it: "behavior.params.cohesion_weight", "drones"
  double min = 0, max = 0;
  bool whole = false;   ///< whole numbers only (the declaration's step 1)
  bool log = false;     ///< searched on a log scale
  double base = 0;      ///< the base test's value: the defaults candidate's
  std::string unit;
};

struct Objective {
  std::string column;           ///< of outcome.csv, or of summary.csv (its last row, or the row at `at`)
  bool from_summary = false;    ///< read from summary.csv (the column is not in outcome.csv, or `at` is given)
  std::optional<double> at;     ///< s: summary.csv's last row at or before this time
  bool maximise = true;
  enum class Aggregate { mean, median, quantile } aggregate = Aggregate::mean;
  double quantile = 0.5;        ///< for Aggregate::quantile
  /// "targets_found", "targets_found@300" (the name in tune.csv's header).
  std::string name() const;
  /// "mean", "median", "quantile 0.25".
  std::string aggregate_name() const;
  /// The aggregate of one candidate's values over worlds (linear-interpolated quantiles).
  double aggregate_of(std::vector<double> values) const;
};

struct Racing {
  bool on = false;
  double level = 0.05;          ///< one-sided level of the paired t-test that drops a candidate
  std::size_t first_test = 5;   ///< worlds every candidate runs before the first test
};

struct TuneSpec {
  std::string source;                 ///< the file, as messages name it
  std::string world;                  ///< a "world" from a queue: "QUEUE: test NAME, condition C"; "" for a "test"
  std::string test_json;              ///< the base test as JSON text (a test object)
  std::filesystem::path base_dir;     ///< relative paths in the test are relative to this
  TestSpec base;                      ///< the base test, read
  std::vector<TuneParameter> parameters;
  std::vector<Objective> objectives;
  std::string algorithm = "cmaes";
  std::size_t population = 0;         ///< candidates per generation (0: the algorithm's default)
  std::string local;                  ///< a local finish with NLopt ("bobyqa", "neldermead"), or ""
  std::size_t local_evaluations = 0;  ///< the finish's share of the budget
  std::uint64_t seed = 1;
  std::size_t evaluations = 0;        ///< budget: tests run for tuning (0: no limit but `seconds`)
  double seconds = 0;                 ///< budget: wall time (0: no limit but `evaluations`)
  std::size_t worlds = 10;            ///< tuning worlds: repeats 0 … worlds − 1 of the paired seed rule
  std::size_t validation_worlds = 10; ///< held out: repeats worlds … worlds + validation_worlds − 1
  std::size_t validation_candidates = 3;
  Racing racing;
  /// The file's content as canonical JSON (what OUT/tune.json records, and --resume compares).
  std::string canonical;
};

/// A number of a test that a tune file can tune: its key, declaration and the test's value.
struct TunableNumber {
  std::string key;   ///< as a tune file's "parameters" (and sweep.set) take it: "behavior.params.k", "groups.a.drones"
  Parameter spec;    ///< the declared range, step (1: whole numbers) and unit
  double value = 0;  ///< the test's value
  bool log = false;  ///< searched on a log scale unless the tune file says otherwise (docs/tuning.md)
};

/// Every tunable number of `test`, per group its behavior's parameters, drone count and drone
/// properties, then the comm fields (with "comm"), the wind's numbers (with wind), the failure clocks,
/// the map's and the targets' parameters. What the desktop's Tune page offers.
std::vector<TunableNumber> tunable_numbers(const TestSpec& test, const PluginHost& host);

/// The algorithms by name, for messages: "random, lhs, grid, cmaes, xnes, pso, de, nsga2, bobyqa, neldermead".
const std::vector<std::string>& tune_algorithms();

/// What salsa tune's command line changes in a tune file (each recorded in OUT/tune.json).
struct TuneOverrides {
  std::optional<std::uint64_t> seed;         ///< --seed: over the file's
  std::optional<double> time;                ///< --time (s): every evaluation's test time, as salsa run --time sets it
  std::optional<double> evaluations;         ///< --evaluations: the budget's count of evaluations (a whole number, checked)
};

/// Reads and checks a tune file with the command line's overrides. Throws InputError.
TuneSpec load_tune(const std::filesystem::path& file, const PluginHost& host, const TuneOverrides& overrides = {});

/// The candidate's test: the base with each parameter set to `values` (in spec order), named `name`,
/// on world `world` (its paired seed from the tune's seed). Throws InputError when the test reader
/// refuses the values (a combination the declarations allow one by one, but the test does not).
TestSpec candidate_test(const TuneSpec& spec, const std::vector<double>& values, const std::string& name, std::size_t world,
                        const PluginHost& host);

}  // namespace salsa
