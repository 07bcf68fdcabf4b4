#pragma once
// The metrics a test asked for (TestSpec::metrics), created through the host and driven by the runner:
// their step columns go into summary.csv, their final columns into outcome.csv (docs/output-format.md).
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {

/// summary.csv's own columns, before any metric's.
inline constexpr const char* summary_columns = "time,targets_found,fraction_found,mean_speed,max_speed,mean_nn_distance,collisions";
/// outcome.csv's own columns, before any metric's.
inline constexpr const char* outcome_columns = "targets,targets_found,fraction_found";

/// A list of metrics that cannot go together, or one that cannot be made: `index` is the metric at
/// fault (metrics[index]), the message says why (names and columns, what is allowed).
struct MetricListError : std::runtime_error {
  MetricListError(std::size_t i, const std::string& what) : std::runtime_error(what), index(i) {}
  std::size_t index;
};

/// A metric threw while the test ran; the message names the metric, its file and the time.
struct MetricFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class MetricSet {
 public:
  /// Creates the metrics and checks their columns: valid names, no clash with salsa's own columns or
  /// with each other. Throws MetricListError.
  MetricSet(const std::vector<PluginChoice>& metrics, const PluginHost& host);
  /// The same for a test; throws InputError naming the test's source and metrics[i].
  MetricSet(const TestSpec& test, const PluginHost& host);
  ~MetricSet();
  MetricSet(const MetricSet&) = delete;
  MetricSet& operator=(const MetricSet&) = delete;

  std::vector<std::string> step_columns() const;   ///< appended to summary.csv's header
  std::vector<std::string> final_columns() const;  ///< appended to outcome.csv's header

  // Each throws MetricFailure when a metric throws.
  void start(const Simulation& sim);       ///< at time 0
  void after_step(const Simulation& sim);  ///< after every step (a step already seen is skipped)
  void row(const Simulation& sim, CsvWriter& csv);  ///< at each logged row: appends the step columns' fields
  std::vector<double> observe(const Simulation& sim);  ///< the step columns' values now (NaN: empty), in order
  std::vector<std::pair<std::string, std::string>> finish(const Simulation& sim);  ///< final (column, text)

 private:
  struct Slot;
  class View;
  template <class Call>
  void each(const Simulation& sim, const char* what, Call call);
  std::vector<Slot> slots_;
  std::unique_ptr<View> view_;
  std::uint64_t stepped_ = 0;  // the simulation step the metrics have seen
};

/// outcome.csv's text: header and one row (targets, found, fraction, then `finals`).
std::string outcome_csv(const Simulation& sim, const std::vector<std::pair<std::string, std::string>>& finals);

}  // namespace salsa
