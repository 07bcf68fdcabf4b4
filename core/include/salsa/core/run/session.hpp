#pragma once
// One run of a test: the Simulation and everything that runs with it — the test's metrics, the
// timeline of timed changes and the summary row. `salsa run` (runner.hpp: files), the desktop's
// sandbox (gui-qt engine: snapshots, pacing) and the plugin fixture all step through a Session, so a
// sandbox session, the test it saves and `salsa run` of that test execute the same code.
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/run/metrics.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {

/// A test failed while running (a plugin threw, a change could not be applied): one line naming the
/// test, the plugin or the change, and the time. The other tests of a queue may go on.
struct TestFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// summary.csv's own numbers at one moment (docs/output-format.md); the desktop's live plots show the
/// same numbers.
struct SummaryRow {
  double time = 0;                    ///< s
  std::size_t targets_found = 0;
  double fraction_found = 0;          ///< of all targets; 0 without targets
  double mean_speed = 0;              ///< m/s, over the drones flying now
  double max_speed = 0;               ///< m/s
  /// m: each drone's nearest other drone, averaged over the drones that have one; NaN alone.
  double mean_nn_distance = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t collisions = 0;       ///< contacts begun so far
};
SummaryRow summary_row(const Simulation& sim);

/// A drone's status as the outputs write it: flying, camera_failed, returning, charging, outbound
/// (return to base's errands), landed, failed or removed.
const char* status_name(const Simulation& sim, std::uint32_t id);

/// The plugin a PluginFailure is about, as `test` chose it: "contact handler 'h' (/path/libh.so)"
/// (without the file when the host no longer knows the name).
std::string failed_plugin(const PluginFailure& failure, const TestSpec& test, const PluginHost& host);

struct SessionOptions {
  int threads = 0;                     ///< decide threads (SimulationSetup::threads); 0: all cores
  std::shared_ptr<Behavior> behavior;  ///< replaces the test's behavior (the plugin fixture)
};

class Session {
 public:
  /// Builds the test's simulation and its metrics, started at time 0. Throws TestFailure: "test 'x'
  /// (file): could not start: why" (bad input found by make_setup, a plugin refusing), or a metric's
  /// failure at time 0.
  Session(TestSpec test, const PluginHost& host, SessionOptions options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Applies the timeline's changes due before the next step, steps the simulation (its observers see
  /// the log interval's rows) and then the metrics. Throws TestFailure (one line), or WriteError from an
  /// observer's file. May go on past the test's time (the sandbox does).
  void step();
  /// The test's time reached: `salsa run` stops here.
  bool finished() const;
  /// A live change now, recorded in the timeline after the changes already at this time (so a test
  /// with this timeline replays it). Throws std::invalid_argument or what the plugin threw when it is
  /// refused; nothing changed then.
  void change(const std::string& key, double value);
  /// Hot reload (the desktop): the plugins of a rescan from now on, and, when `behavior` is given, the
  /// running behavior of `group` replaced where the drones are (fresh per-drone memory), `params` its values.
  /// Throws what the simulation or plugin throws; nothing changed then.
  void use_plugins(const PluginHost& host, std::shared_ptr<Behavior> behavior = nullptr, ParameterValues params = {},
                   std::uint32_t group = 0);
  /// The metrics' final columns (outcome.csv). Throws TestFailure.
  std::vector<std::pair<std::string, std::string>> finish();

  void add_observer(Observer* observer) { sim_->add_observer(observer); }
  Simulation& simulation() { return *sim_; }
  const Simulation& simulation() const { return *sim_; }
  MetricSet& metrics() { return *metrics_; }
  const PluginHost& host() const { return *host_; }
  /// The test as given: the start state, its changes the timeline it started with.
  const TestSpec& test() const { return test_; }
  /// The test as the changes so far left it (behavior parameters, drone count and configuration).
  const TestSpec& current() const { return current_; }
  /// Every change, applied or due, in time order: the test's own and the live ones.
  const std::vector<Change>& timeline() const { return timeline_; }
  /// How many of the timeline's changes have been applied (the first ones).
  std::size_t changes_applied() const { return next_change_; }
  /// "test 'x' (file.json)": how messages name this run.
  std::string where() const;

 private:
  void apply_due_changes();

  TestSpec test_, current_;
  const PluginHost* host_;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<MetricSet> metrics_;
  std::vector<Change> timeline_;
  std::size_t next_change_ = 0;  // timeline_[next_change_...] are not applied yet
};

}  // namespace salsa
