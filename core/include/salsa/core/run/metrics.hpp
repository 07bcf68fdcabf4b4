#pragma once
// The metrics a test asked for (TestSpec::metrics), made by make_metrics (metric_list.hpp) and driven by
// the runner: their step columns go into summary.csv, their final columns into outcome.csv
// (docs/output-format.md).
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/metric_list.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {

/// A metric threw while the test ran; the message names the metric, its file and the time.
struct MetricFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class MetricSet {
 public:
  /// Makes the metrics (make_metrics: throws MetricListError, or InputError for a test).
  MetricSet(const std::vector<PluginChoice>& metrics, const PluginHost& host);
  MetricSet(const TestSpec& test, const PluginHost& host);
  explicit MetricSet(std::vector<MetricSlot> metrics);
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
