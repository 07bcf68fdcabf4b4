#pragma once
// Running a queue: tests side by side (--jobs), started in queue order, with progress, per-test plots
// drawn as each test ends, and the indices coming from a Dispatch (all of them, a shard, or MPI).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::cli {

/// Where this process's tests come from; called on the main thread only.
class Dispatch {
 public:
  virtual ~Dispatch() = default;
  /// The next test (an index into the queue) for this process, nullopt when there are none left.
  virtual std::optional<std::size_t> next() = 0;
  /// Called between events, a few times a second (MPI rank 0 answers the other ranks here).
  virtual void serve() {}
  /// Whether every process taking part has finished (MPI rank 0 waits for the others' reports).
  virtual bool all_done() { return true; }
  /// This process has run everything it was given; `failed` of them failed.
  virtual void finished(std::size_t /*failed*/) {}
};

/// The tests at `indices`, in that order: every test, or a shard's share.
class ListDispatch final : public Dispatch {
 public:
  explicit ListDispatch(std::vector<std::size_t> indices) : indices_(std::move(indices)) {}
  std::optional<std::size_t> next() override {
    if (at_ == indices_.size()) return std::nullopt;
    return indices_[at_++];
  }

 private:
  std::vector<std::size_t> indices_;
  std::size_t at_ = 0;
};

struct QueueRunOptions {
  std::size_t jobs = 1;       ///< tests at once
  bool quiet = false;         ///< no progress (errors still go to stderr)
  bool plots = true;          ///< draw each finished test's plots (plots::draw_test_plots)
  bool terminal = false;      ///< progress as a live bar (else one line per finished test)
  std::size_t expected = 0;   ///< tests this process expects to run, for the progress (0: all)
  std::string label;          ///< shown before the live bar (salsa tune: where the tune stands)
  /// --isolate: runs one test in its own process and returns (wait status, what it wrote on stderr).
  std::function<std::pair<int, std::string>(const TestSpec&)> isolated;
};

struct QueueResult {
  int status = 0;             ///< 0, 1 when a test failed, 128 + the signal when interrupted
  bool write_failed = false;  ///< a write failed (a full disk?): no test was started after it
};

/// Runs the tests the dispatch hands out. Failures are printed on stderr (one line each); an
/// interruption gets one line naming every test it stopped.
QueueResult run_queue(const std::vector<TestSpec>& tests, const PluginHost& host, const RunOptions& options,
              const QueueRunOptions& run, Dispatch& dispatch);

/// The "[i/n] name: ..." line's end for a finished test folder (from its files): "2.00 s simulated in
/// 0.01 s, 1/3 targets found -> out/a".
std::string finished_line(const TestSpec& test, const std::filesystem::path& folder, double wall_seconds);

}  // namespace salsa::cli
