#pragma once
// The sandbox's run, on a worker thread: a core Session (the same run loop as `salsa run`). The GUI never
// touches it: it posts commands, which the worker applies between steps (live changes go through
// Session::change and are recorded in its timeline), and reads the latest immutable Snapshot, which the worker publishes a few dozen times a
// second. No widgets here (tests drive it directly).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "snapshot.hpp"

namespace salsa::gui {

/// How the worker paces the simulation.
struct Pacing {
  enum Mode { real_time, steps_per_frame, fastest } mode = real_time;
  int steps = 1;        ///< steps_per_frame: whole steps per frame (1/60 s of wall time)
  int dt_factor = 1;    ///< > 1: the larger time step dt × factor (fast, inexact; not recorded as a test)
};

class Engine {
 public:
  explicit Engine(std::shared_ptr<const PluginHost> host);
  explicit Engine(const PluginHost& host);  ///< not owned: it outlives the engine
  ~Engine();  ///< stops the worker
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Commands. Each returns at once; the future gives "" once applied, or the one-line reason it was
  // refused, in which case nothing changed.
  /// A new start state: builds a session for `test` (paused, time 0); the test's own timed changes are
  /// the timeline and apply as it runs, exactly as in `salsa run`.
  std::future<std::string> load(TestSpec test);
  /// Threads the simulation steps on from the next load or reset (0, the default: every core). Any
  /// count gives the same results byte for byte.
  void set_threads(int threads);
  /// Rebuilds the loaded test's start state (paused, time 0): live changes dropped, the test's own kept.
  std::future<std::string> reset();
  /// A live change (keys as in salsa/core/experiments/changes.hpp), recorded at the current time.
  std::future<std::string> set(std::string key, double value);
  void start();
  void pause();
  /// One step (exact), then paused.
  std::future<std::string> step_once();
  /// Fails (returns the reason) when dt_factor makes the step too long for the physics (check_drone).
  std::future<std::string> set_pacing(Pacing pacing);
  void select(std::optional<std::uint32_t> drone);
  /// The plugins of a rescan, used from now on (resets, loads). `rebuilt`: behaviors whose files were
  /// rebuilt: every group running one switches to the new code where it is (positions and velocities
  /// kept, parameter values kept where the new code still declares them, per-drone memory fresh).
  /// Refused for a group (its old code keeps running, and the groups after it are not tried) when the
  /// new code has no such behavior or refuses the values. After a reload, as_test is refused until the
  /// next reset.
  std::future<std::string> use_plugins(std::shared_ptr<const PluginHost> host, std::vector<std::string> rebuilt = {});
  /// The behavior each group runs, in group order (empty before a load).
  std::vector<std::string> behavior_names() const;
  /// Trail samples kept per drone (0: none) and taken every `every` steps.
  void set_trails(std::size_t length, std::size_t every);

  /// The latest snapshot (never null; an empty scene before the first load). Never waits on the worker
  /// beyond a pointer copy.
  std::shared_ptr<const Snapshot> snapshot() const;

  /// The start state plus the timeline of changes so far, `time` set to now: `salsa run` of it replays
  /// this session. Refused (std::nullopt, `why` set) after the inexact larger step was used.
  std::optional<TestSpec> as_test(std::string* why = nullptr) const;
  /// Every change, applied or still due: the test's own and the live ones, in time order.
  std::vector<Change> timeline() const;
  /// The loaded test as the live changes left it (what the controls should show); nullopt before a load.
  std::optional<TestSpec> current_test() const;

  /// Called on the worker thread with a snapshot taken exactly at every multiple of `interval` s of
  /// simulated time (for recordings whose timing does not depend on the machine); nullptr stops it.
  /// The worker waits for the callback to return.
  void on_frame(double interval, std::function<void(std::shared_ptr<const Snapshot>)> callback);

  /// Blocks until every command posted so far has been applied (tests, and before saving).
  void sync();

 private:
  struct Worker;
  std::unique_ptr<Worker> worker_;
};

}  // namespace salsa::gui
