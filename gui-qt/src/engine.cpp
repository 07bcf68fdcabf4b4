// The sandbox's worker: one thread owns the Simulation. Commands run between steps; after each tick
// (1/60 s of wall time) and each command the worker publishes a new immutable Snapshot (engine_snapshot.cpp).
#include "engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "engine_worker.hpp"
#include "format.hpp"

namespace salsa::gui {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto tick = std::chrono::microseconds(16'667);  // one frame at 60 Hz
constexpr int heat_cells = 128;                           // along the map's long side

}  // namespace

Engine::Worker::Worker(std::shared_ptr<const PluginHost> h) : host(std::move(h)) {
  publish_empty();
  thread = std::thread([this] { loop(); });
}

Engine::Worker::~Worker() {
  post([this] { quit = true; });
  thread.join();
}

void Engine::Worker::loop() {
  auto next_tick = Clock::now();
  while (true) {
    std::deque<std::function<void()>> todo;
    {
      std::unique_lock lock(command_mutex);
      if (commands.empty() && !(state == RunState::running && sim))
        wake.wait(lock, [&] { return !commands.empty(); });
      todo.swap(commands);
    }
    for (auto& fn : todo) fn();
    if (quit) return;
    if (!todo.empty()) publish(true);
    if (state != RunState::running || !sim) {
      next_tick = Clock::now();
      continue;
    }
    run_tick();
    publish();
    // Paced modes wait for the next frame (woken early by a command); fastest goes straight on.
    if (pacing.mode != Pacing::fastest) {
      next_tick += tick;
      const auto now = Clock::now();
      if (next_tick < now) next_tick = now;
      std::unique_lock lock(command_mutex);
      wake.wait_until(lock, next_tick, [&] { return !commands.empty(); });
    }
  }
}

void Engine::Worker::run_tick() {
  const auto began = Clock::now();
  auto more = [&](std::size_t done) {
    switch (pacing.mode) {
      case Pacing::steps_per_frame: return done < static_cast<std::size_t>(std::max(1, pacing.steps));
      case Pacing::fastest: return Clock::now() - began < tick;
      case Pacing::real_time: {
        // Simulated time follows the wall clock, at most a quarter second behind (no catching up).
        const double wall = seconds(Clock::now() - anchor_wall);
        if (wall - (sim->time() - anchor_time) > 0.25) {
          anchor_time = sim->time();
          anchor_wall = Clock::now() - std::chrono::milliseconds(250);
        }
        return sim->time() - anchor_time + sim->dt() / 2 < seconds(Clock::now() - anchor_wall) &&
               Clock::now() - began < tick;
      }
    }
    return false;
  };
  for (std::size_t done = 0; more(done) && state == RunState::running; ++done) step();
}

void Engine::Worker::step() {
  try {
    session->step();
  } catch (const std::exception& e) {  // one line naming the test and the plugin, as salsa run says it
    error = e.what();
    state = RunState::failed;
    return;
  }
  if (pause_at_end && session->finished()) {
    pause_at_end = false;
    if (state == RunState::running) state = RunState::paused;
  }
  after_step();
}

void Engine::Worker::after_step() {
  const auto positions = sim->drone_positions();
  if (trail_ring.size() != positions.size() * trail_length) drone_count_changed();  // a timed change
  // Heat: one visit per flying drone per step (a stopped drone is no visit).
  const auto status = sim->drone_status();
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (status[i] != DroneStatus::flying) continue;
    const Vec2 p = positions[i];
    const int c = std::clamp(static_cast<int>((p.x - heat_grid.origin.x) / heat_grid.cell), 0, heat_grid.cols - 1);
    const int r = std::clamp(static_cast<int>((p.y - heat_grid.origin.y) / heat_grid.cell), 0, heat_grid.rows - 1);
    ++heat_counts[static_cast<std::size_t>(r) * heat_grid.cols + c];
  }
  if (trail_length > 0 && sim->step_count() % trail_every == 0) {
    const std::size_t slot = trail_taken % trail_length;
    for (std::size_t d = 0; d < positions.size(); ++d) trail_ring[d * trail_length + slot] = positions[d];
    ++trail_taken;
    trails_published.reset();
  }
  if (sim->targets_found() != found_count) {
    const auto& targets = sim->targets();
    for (std::size_t i = 0; i < targets.size(); ++i) found[i] = targets[i].found() ? 1 : 0;
    found_count = sim->targets_found();
    ++found_version;
  }
  if (sim->step_count() % start.log_every() == 0 && !add_stats_row()) return;
  if (frame_callback) {
    const auto every = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(frame_interval / sim->dt())));
    if (sim->step_count() % every == 0) frame_callback(make_snapshot());
  }
}

bool Engine::Worker::add_stats_row() {
  const SummaryRow summary = summary_row(*sim);
  StatsRow row;
  row.time = summary.time;
  row.found_percent = 100 * summary.fraction_found;
  row.mean_speed = summary.mean_speed;
  row.mean_nn_distance = summary.mean_nn_distance;
  row.coverage_percent = std::numeric_limits<double>::quiet_NaN();
  if (coverage_column) {
    try {
      row.coverage_percent = 100 * session->metrics().observe(*sim)[*coverage_column];
    } catch (const std::exception& e) {
      error = session->where() + ": " + e.what();
      state = RunState::failed;
      return false;
    }
  }
  auto rows = std::make_shared<std::vector<StatsRow>>(*stats);  // published rows are never touched again
  rows->push_back(row);
  stats = std::move(rows);
  return true;
}

std::string Engine::Worker::load(TestSpec test) {
  std::unique_ptr<Session> next;
  try {
    // All cores, as salsa run (the results are the same for any thread count): the step's workers
    // idle between steps, and a swarm too big for real time is stepped as fast as the cores allow.
    next = std::make_unique<Session>(test, *host, SessionOptions{threads, nullptr});
  } catch (const std::exception& e) {
    return e.what();
  }
  // Nothing below throws (but for memory): the new start state replaces the old one whole.
  session = std::move(next);
  sim = &session->simulation();
  coverage_column.reset();
  const auto columns = session->metrics().step_columns();
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == "coverage") coverage_column = i;  // area_coverage's
  start = std::move(test);
  state = RunState::paused;
  pause_at_end = true;
  error.clear();
  inexact_used = false;
  reloaded_at.reset();
  pacing.dt_factor = 1;
  selected.reset();
  scene = scene_of(*sim);
  found.assign(sim->targets().size(), 0);
  found_count = 0;
  ++found_version;
  reset_trails();
  const Rect b = sim->bounds();
  heat_grid = {};
  heat_grid.origin = b.min;
  heat_grid.cell = std::max(b.width(), b.height()) / heat_cells;
  heat_grid.cols = std::max(1, static_cast<int>(std::ceil(b.width() / heat_grid.cell)));
  heat_grid.rows = std::max(1, static_cast<int>(std::ceil(b.height() / heat_grid.cell)));
  heat_counts.assign(static_cast<std::size_t>(heat_grid.cols) * heat_grid.rows, 0);
  heat.reset();
  stats = std::make_shared<std::vector<StatsRow>>();
  add_stats_row();  // time 0
  speed_samples.clear();
  return {};
}

void Engine::Worker::drone_count_changed() {
  reset_trails();
  if (selected && (*selected >= sim->drone_count() || sim->drone_status()[*selected] == DroneStatus::removed)) selected.reset();
}

void Engine::Worker::reset_trails() {
  trail_taken = 0;
  trails_published.reset();
  trail_ring.assign(sim ? sim->drone_count() * trail_length : 0, Vec2{std::numeric_limits<double>::quiet_NaN(), 0});
}

std::string Engine::Worker::set(const std::string& key, double value) {
  if (!sim) return "no test loaded";
  if (state == RunState::failed) return "the run stopped: " + error + " (reset to go on)";
  try {
    session->change(key, value);
  } catch (const std::exception& e) {
    return e.what();
  }
  if (key.ends_with("drones")) drone_count_changed();
  return {};
}

std::string Engine::Worker::use_plugins(std::shared_ptr<const PluginHost> next, const std::vector<std::string>& rebuilt) {
  for (std::uint32_t g = 0; sim && g < start.groups.size(); ++g) {
    const std::string name = session->current().groups[g].behavior.name;
    if (std::find(rebuilt.begin(), rebuilt.end(), name) == rebuilt.end()) continue;
    const std::string whose = start.groups.size() > 1 ? "group '" + start.groups[g].name + "': " : "";
    try {
      const auto& entry = next->behavior(name);
      auto kept = [&](const ParameterValues& old) {  // the new declaration, with the old values it allows
        ParameterValues values(entry.factory.parameters);
        for (const auto& p : entry.factory.parameters)
          if (old.has(p.name) && old.get(p.name) >= p.min && old.get(p.name) <= p.max) values.set(p.name, old.get(p.name));
        return values;
      };
      const ParameterValues values = kept(session->current().groups[g].behavior.params);
      session->use_plugins(*next, PluginHost::create(entry, values), values, g);
      start.groups[g].behavior.params = kept(start.groups[g].behavior.params);
      reloaded_at = sim->time();
      if (state == RunState::failed) state = RunState::paused, error.clear();
    } catch (const PluginFailure& e) {  // the new code's reset threw
      return whose + "the old code keeps running: " + failed_plugin(e, session->current(), *next) + " failed: " + e.what();
    } catch (const std::exception& e) {
      return whose + "the old code keeps running: " + e.what();
    }
  }
  if (session) session->use_plugins(*next);
  host = std::move(next);
  return {};
}

void Engine::Worker::start_running() {
  if (!sim || state == RunState::failed) return;
  state = RunState::running;
  anchor_wall = Clock::now();
  anchor_time = sim->time();
}


Engine::Engine(std::shared_ptr<const PluginHost> host) : worker_(std::make_unique<Worker>(std::move(host))) {}
Engine::Engine(const PluginHost& host) : Engine(std::shared_ptr<const PluginHost>(&host, [](const PluginHost*) {})) {}
Engine::~Engine() = default;

void Engine::set_threads(int threads) {
  worker_->post([w = worker_.get(), threads] { w->threads = std::max(0, threads); });
}

std::future<std::string> Engine::load(TestSpec test) {
  return worker_->ask<std::string>([w = worker_.get(), test = std::move(test)]() mutable { return w->load(std::move(test)); });
}

std::future<std::string> Engine::reset() {
  return worker_->ask<std::string>([w = worker_.get()] { return w->sim ? w->load(w->start) : std::string("no test loaded"); });
}

std::future<std::string> Engine::set(std::string key, double value) {
  return worker_->ask<std::string>([w = worker_.get(), key = std::move(key), value] { return w->set(key, value); });
}

void Engine::start() {
  worker_->post([w = worker_.get()] { w->start_running(); });
}

void Engine::pause() {
  worker_->post([w = worker_.get()] {
    if (w->state == RunState::running) w->state = RunState::paused;
  });
}

std::future<std::string> Engine::step_once() {
  return worker_->ask<std::string>([w = worker_.get()]() -> std::string {
    if (!w->sim) return "no test loaded";
    if (w->state == RunState::failed) return "the run stopped: " + w->error + " (reset to go on)";
    w->state = RunState::paused;
    w->step();
    return w->state == RunState::failed ? w->error : "";
  });
}

std::future<std::string> Engine::set_pacing(Pacing pacing) {
  return worker_->ask<std::string>([w = worker_.get(), pacing]() -> std::string {
    if (w->sim) {
      const double dt = w->start.dt * std::max(1, pacing.dt_factor);
      if (dt != w->sim->dt()) {
        try {
          w->sim->set_dt(dt);
        } catch (const std::exception& e) {
          return "larger time step ×" + std::to_string(pacing.dt_factor) + " refused: " + e.what();
        }
      }
      if (pacing.dt_factor > 1) w->inexact_used = true;
    }
    w->pacing = pacing;
    w->anchor_wall = Clock::now();
    w->anchor_time = w->sim ? w->sim->time() : 0;
    return {};
  });
}

void Engine::select(std::optional<std::uint32_t> drone) {
  worker_->post([w = worker_.get(), drone] { w->selected = drone; });
}

void Engine::set_trails(std::size_t length, std::size_t every) {
  worker_->post([w = worker_.get(), length, every] {
    w->trail_length = length;
    w->trail_every = std::max<std::size_t>(1, every);
    w->reset_trails();
  });
}

std::shared_ptr<const Snapshot> Engine::snapshot() const {
  std::lock_guard lock(worker_->snapshot_mutex);
  return worker_->published;
}

std::optional<TestSpec> Engine::as_test(std::string* why) const {
  auto answer = worker_->ask<std::pair<std::optional<TestSpec>, std::string>>(
      [w = worker_.get()]() -> std::pair<std::optional<TestSpec>, std::string> {
        if (!w->sim) return {std::nullopt, "no test loaded"};
        if (w->inexact_used)
          return {std::nullopt, "this run used the larger time step (inexact), so no test can replay it; reset and run at the test's own step to save it"};
        if (w->reloaded_at)
          return {std::nullopt, "the behavior's code was reloaded at t = " + format::seconds(*w->reloaded_at) +
                                    " s, and a test replays one version of it; reset, then run and save"};
        TestSpec t = w->start;
        t.time = std::max(w->sim->time(), t.dt);
        t.changes.clear();  // the timeline up to now: what this session applied
        for (const Change& c : w->session->timeline())
          if (change_step(c.time, t.dt) <= w->sim->step_count()) t.changes.push_back(c);
        t.seed_given = true;
        return {std::move(t), ""};
      });
  auto [test, reason] = answer.get();
  if (why) *why = reason;
  return test;
}

std::future<std::string> Engine::use_plugins(std::shared_ptr<const PluginHost> host, std::vector<std::string> rebuilt) {
  return worker_->ask<std::string>([w = worker_.get(), host = std::move(host), rebuilt = std::move(rebuilt)]() mutable {
    return w->use_plugins(std::move(host), rebuilt);
  });
}

std::vector<std::string> Engine::behavior_names() const {
  return worker_->ask<std::vector<std::string>>([w = worker_.get()] {
    std::vector<std::string> names;
    if (w->sim)
      for (const GroupSpec& g : w->session->current().groups) names.push_back(g.behavior.name);
    return names;
  }).get();
}

std::vector<Change> Engine::timeline() const {
  return worker_->ask<std::vector<Change>>([w = worker_.get()] {
    return w->session ? w->session->timeline() : std::vector<Change>{};
  }).get();
}

std::optional<TestSpec> Engine::current_test() const {
  return worker_->ask<std::optional<TestSpec>>([w = worker_.get()]() -> std::optional<TestSpec> {
    if (!w->sim) return std::nullopt;
    return w->session->current();
  }).get();
}

void Engine::on_frame(double interval, std::function<void(std::shared_ptr<const Snapshot>)> callback) {
  worker_->ask<int>([w = worker_.get(), interval, callback = std::move(callback)]() mutable {
    w->frame_interval = interval;
    w->frame_callback = interval > 0 ? std::move(callback) : nullptr;
    return 0;
  }).get();
}

void Engine::sync() { worker_->ask<int>([] { return 0; }).get(); }

}  // namespace salsa::gui
