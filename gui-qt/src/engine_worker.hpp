#pragma once
// The engine's worker (private to the engine's files): the thread that owns the session, its state and commands.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "engine.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/run/session.hpp"

namespace salsa::gui {

struct Engine::Worker {
  using Clock = std::chrono::steady_clock;
  static double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

  explicit Worker(std::shared_ptr<const PluginHost> h);
  ~Worker();

  std::shared_ptr<const PluginHost> host;  // swapped by use_plugins; objects made from an old one keep its libraries
  std::thread thread;

  // Commands, run on the worker between steps.
  std::mutex command_mutex;
  std::condition_variable wake;
  std::deque<std::function<void()>> commands;
  bool quit = false;

  // The published snapshot.
  mutable std::mutex snapshot_mutex;
  std::shared_ptr<const Snapshot> published;

  // ---- Worker-only state ----
  TestSpec start;  // the start state (its behavior parameters follow a hot reload)
  std::unique_ptr<Session> session;  // the run: simulation, metrics, timeline (the same code as salsa run)
  Simulation* sim = nullptr;         // session's
  std::optional<std::size_t> coverage_column;  // the area_coverage metric's column, when the test has it
  std::shared_ptr<const Scene> scene;
  RunState state = RunState::paused;
  /// Until the test's time is reached once after a load or reset: the step that reaches it pauses
  /// (exactly there, whatever the pacing); a Start after it runs on.
  bool pause_at_end = true;
  std::string error;
  int threads = 0;  // 0: every core
  Pacing pacing;
  bool inexact_used = false;
  std::optional<double> reloaded_at;  // the behavior's code was swapped then: no test replays two versions
  std::optional<std::uint32_t> selected;
  // Real-time pacing: the wall time and simulated time it counts from.
  Clock::time_point anchor_wall;
  double anchor_time = 0;
  // Speed: (wall, simulated) samples over the last second or so.
  std::deque<std::pair<Clock::time_point, double>> speed_samples;
  // Found targets.
  std::vector<std::uint8_t> found;
  std::size_t found_count = 0;
  std::uint64_t found_version = 0;
  // Trails: a ring of trail_length samples per drone.
  std::size_t trail_length = 64, trail_every = 6, trail_taken = 0;
  std::vector<Vec2> trail_ring;
  std::shared_ptr<const std::vector<Vec2>> trails_published;  // the ring oldest first, until it changes
  // Heat map: visits per cell, normalised when published.
  HeatMap heat_grid;
  std::vector<std::uint32_t> heat_counts;
  std::shared_ptr<const HeatMap> heat;
  Clock::time_point heat_published;
  // Live plot rows.
  std::shared_ptr<const std::vector<StatsRow>> stats = std::make_shared<std::vector<StatsRow>>();
  // Recording frames.
  double frame_interval = 0;
  std::function<void(std::shared_ptr<const Snapshot>)> frame_callback;

  void post(std::function<void()> fn) {
    {
      std::lock_guard lock(command_mutex);
      commands.push_back(std::move(fn));
    }
    wake.notify_one();
  }
  template <class R>
  std::future<R> ask(std::function<R()> fn) {
    auto promise = std::make_shared<std::promise<R>>();
    auto future = promise->get_future();
    post([this, promise, fn = std::move(fn)] {
      try {
        auto value = fn();
        publish(true);  // whoever waits on the answer sees its effect in snapshot()
        promise->set_value(std::move(value));
      } catch (...) {
        promise->set_exception(std::current_exception());
      }
    });
    return future;
  }

  // ---- The loop (engine.cpp)
  void loop();
  void run_tick();
  void step();
  void after_step();
  /// The summary row salsa run writes, for the live plots; false (the run failed) when a metric threw.
  bool add_stats_row();

  // ---- Snapshots (engine_snapshot.cpp)
  void publish_empty();
  std::shared_ptr<const Snapshot> make_snapshot();
  /// Whether the outputs would carry the fleet's columns now: the test's fleet model, or a fail.* change made.
  bool fleet_on() const;
  Inspection inspect(std::uint32_t id) const;
  /// `now_all`: the heat map too, whenever it was last drawn (after commands; while running, 4 times a second).
  void publish(bool now_all = false);
  void publish_heat(Clock::time_point now);

  // ---- Commands (engine.cpp)
  std::string load(TestSpec test);
  /// Drones were added or removed: trails start over; a removed drone is no longer selected.
  void drone_count_changed();
  void reset_trails();
  std::string set(const std::string& key, double value);
  /// Plugins from a rescan. Each group whose behavior is in `rebuilt` goes on with the new code: same
  /// parameter values (those the new version still declares, in its ranges), positions and velocities
  /// kept, per-drone memory fresh. If the new code refuses, that group's old code keeps running.
  std::string use_plugins(std::shared_ptr<const PluginHost> next, const std::vector<std::string>& rebuilt);
  void start_running();
};

}  // namespace salsa::gui
