#pragma once
// The columns a test's data files will have, known when the test is read: salsa's own, its metrics'
// (each metric made through the host and its columns checked) and its models'. The reader refuses a
// metric list that clashes and a tune objective that names no column here; run/'s MetricSet drives the
// same metrics while the test runs.
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/plugins/plugin_host.hpp"

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

/// One metric of a test, made, with its columns.
struct MetricSlot {
  std::string label;  ///< "metric 'area_coverage' (/path/libmetrics.so)"
  std::shared_ptr<Metric> metric;
  std::vector<Column> step, final;  ///< summary.csv's and outcome.csv's
};

/// Makes the metrics and checks their columns: valid names, no clash with salsa's own columns, the
/// queue summary's or each other's. Throws MetricListError.
std::vector<MetricSlot> make_metrics(const std::vector<PluginChoice>& metrics, const PluginHost& host);
/// The same for a test; throws InputError naming the test's source and metrics[i].
std::vector<MetricSlot> make_metrics(const TestSpec& test, const PluginHost& host);

/// The columns of summary.csv and outcome.csv a test will write: salsa's, its metrics', its models'.
struct DataColumns {
  std::vector<std::string> summary, outcome;
};
DataColumns data_columns(const TestSpec& test, const PluginHost& host);

/// `list` ("a,b,c") as names.
std::vector<std::string> split_columns(const char* list);

}  // namespace salsa
