// Frame times of the sandbox view for a swarm over a forest with trails on, at 1920×1080, drawn on the
// raster engine exactly as the window draws (FrameRenderer), while the engine runs; then flying as the
// user sees it (real time, each new snapshot drawn); then the simulation's speed with the GUI drawing
// each new snapshot (up to 60 FPS) against the same test headless.
#include "bench_render.hpp"

#include <time.h>

#include <QImage>
#include <QPainter>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <sstream>
#include <thread>
#include <vector>

#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "engine.hpp"
#include "frame_renderer.hpp"

namespace salsa::gui {
namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

/// 12345 → "12,345", as the docs write counts.
std::string grouped(long long n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// The forest-health scale: 2 km × 2 km and 50,000 trees, for up to 10,000 drones.
constexpr int forest_drones = 10000, forest_trees = 50000;
constexpr double forest_side = 2000;

struct Workload {
  double side;  ///< m
  long long trees;
};
Workload workload(int drones) {
  const double grow = std::max(1.0, static_cast<double>(drones) / forest_drones);  // area and trees, past 10,000 drones
  return {std::round(forest_side * std::sqrt(grow)), std::llround(forest_trees * grow)};
}

}  // namespace

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

BenchStats bench_stats(const std::vector<double>& times) {
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) { return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * static_cast<double>(sorted.size())))]; };
  return {std::accumulate(times.begin(), times.end(), 0.0) / static_cast<double>(times.size()), at(0.5), at(0.95), sorted.back()};
}

std::string bench_render_test(const BenchRenderOptions& options) {
  const Workload w = workload(options.drones);
  std::ostringstream json;
  json << R"({"name": "bench-render", "behavior": ")" << options.behavior << R"(", "drones": )" << options.drones
       << R"(, "map": {"name": "empty", "params": {"size": )" << w.side << R"(}}, "targets": {"kind": "tree", "count": )" << w.trees
       << R"(}, "time": 1000000, "seed": 1)" << (options.physics == "box2d" ? "" : R"(, "physics": ")" + options.physics + "\"")
       // Past 10,000 the default disc (drones × radius: 100 km for 100,000) would not fit the map.
       << (options.drones > forest_drones ? R"(, "spawn": {"mode": "uniform"})" : "") << "}";
  return json.str();
}

int bench_render(const PluginHost& host, std::ostream& out, const BenchRenderOptions& options) {
  const BenchRenderOptions defaults;
  out << "salsa-gui --bench-render --frames " << options.frames;
  if (options.drones != defaults.drones || options.physics != defaults.physics)
    out << " --drones " << options.drones << " --physics " << options.physics;
  if (options.behavior != defaults.behavior) out << " --behavior " << options.behavior;
  if (options.seconds != defaults.seconds) out << " --seconds " << options.seconds;
  out << "\n";
  const TestSpec test = parse_test(bench_render_test(options), "bench-render", host);
  const Workload w = workload(options.drones);
  constexpr std::size_t trail_length = 64, trail_every = 6;
  out << "scene: " << grouped(options.drones) << " drones (" << options.behavior << (options.physics == "box2d" ? "" : ", " + options.physics + " physics")
      << (options.drones > forest_drones ? ", spread uniformly" : "") << "), " << grouped(w.trees) << " trees on a " << w.side << " m x " << w.side << " m map, trails of " << trail_length
      << " samples, 1920x1080, raster\n";

  QImage target(1920, 1080, QImage::Format_ARGB32_Premultiplied);
  FrameRenderer renderer;
  ViewOptions view;
  view.trails = true;
  out << std::fixed;
  {
    // 1. Frame times while the engine runs in real time (as a user watches it), once the trails are full:
    // the engine runs flat out until every drone has its 64 samples, however slow the steps.
    Engine engine(host);
    if (const std::string why = engine.load(test).get(); !why.empty()) {
      out << "salsa-gui: " << why << "\n";
      return 1;
    }
    engine.set_trails(trail_length, trail_every);
    engine.set_pacing({Pacing::fastest, 1, 1}).get();
    engine.start();
    while (engine.snapshot()->step < trail_length * trail_every) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    engine.set_pacing({}).get();
    std::vector<double> times, cpu, taken;
    std::vector<double> made;  // each snapshot drawn once
    std::shared_ptr<const Snapshot> shown;
    const QTransform t = fit_transform(engine.snapshot()->scene->map.bounds, QSizeF(1920, 1080));
    for (int i = 0; i < options.frames; ++i) {
      const auto frame = Clock::now();
      // What the sandbox's timer does before drawing: take the latest snapshot, let the last one go.
      auto snap = engine.snapshot();
      if (snap != shown) made.push_back(snap->build_ms);
      shown = std::move(snap);
      taken.push_back(ms_since(frame));
      const auto start = Clock::now();
      const double cpu_start = thread_cpu_ms();
      QPainter painter(&target);
      renderer.draw(painter, target.size(), *shown, view, t);
      painter.end();
      times.push_back(ms_since(start));
      cpu.push_back(thread_cpu_ms() - cpu_start);
      std::this_thread::sleep_until(frame + std::chrono::microseconds(16'667));
    }
    const BenchStats s = bench_stats(times);
    out << std::setprecision(2) << "frames: " << options.frames << "; frame time mean " << s.mean << " ms, median " << s.median
        << " ms, p95 " << s.p95 << " ms, max " << s.max << " ms; " << std::setprecision(0) << 1000 / s.mean
        << " FPS drawable; static layer drawn " << renderer.static_redraws() << " times\n";
    const BenchStats c = bench_stats(cpu);
    out << std::setprecision(2) << "drawing thread's CPU time per frame: mean " << c.mean << " ms, median " << c.median << " ms, p95 " << c.p95 << " ms, max " << c.max << " ms\n";
    const BenchStats m = bench_stats(made), k = bench_stats(taken);
    out << std::setprecision(2) << "snapshots: " << made.size() << " new in " << options.frames << " frames, made on the engine's thread in mean "
        << m.mean << " ms, max " << m.max << " ms; taken by the drawing thread in mean " << k.mean << " ms, max " << k.max << " ms\n";

    // 2. Flying, as the user sees it: the engine paced at 1.0× real time (the sandbox's default) while
    // the view draws each new snapshot on the window's 60 Hz timer. A frame's time runs from one new
    // frame drawn to the next, so it holds the wait for the engine's next snapshot too.
    std::vector<double> gaps;
    const double sim_began = engine.snapshot()->time;
    const auto began = Clock::now();
    auto last_drawn = began, tick = began;
    while (ms_since(began) < options.seconds * 1000) {
      if (auto snap = engine.snapshot(); snap != shown) {
        shown = std::move(snap);
        QPainter painter(&target);
        renderer.draw(painter, target.size(), *shown, view, t);
        painter.end();
        const auto now = Clock::now();
        gaps.push_back(std::chrono::duration<double, std::milli>(now - last_drawn).count());
        last_drawn = now;
      }
      tick = std::max(tick + std::chrono::microseconds(16'667), Clock::now());  // a late timer fires once, as QTimer's
      std::this_thread::sleep_until(tick);
    }
    const double wall = ms_since(began) / 1000, rtf = (engine.snapshot()->time - sim_began) / wall;
    engine.pause();
    out << std::setprecision(2) << "flying at 1.0x real time for " << wall << " s, each new snapshot drawn: " << gaps.size() << " frames, "
        << std::setprecision(1) << static_cast<double>(gaps.size()) / wall << " FPS; real-time factor " << std::setprecision(2) << rtf;
    if (gaps.empty()) {
      out << "; no new snapshot in that time\n";
    } else {
      const BenchStats f = bench_stats(gaps);
      out << "; frame time mean " << f.mean << " ms, median " << f.median << " ms, p95 " << f.p95 << " ms, max " << f.max << " ms\n";
    }
  }

  // 3. Simulation speed: the engine flat out while the GUI draws each new snapshot, at most 60 a second
  // (as the sandbox's timer does), against headless.
  const double seconds = 5;
  auto steps_per_second_headless = [&] {
    Simulation sim(make_setup(test, host, 0));  // all cores, as the engine
    const auto start = Clock::now();
    while (ms_since(start) < seconds * 1000) sim.step();
    return sim.time() / (ms_since(start) / 1000);
  };
  const double headless = steps_per_second_headless();
  Engine gui(host);
  gui.load(test).get();
  gui.set_trails(trail_length, trail_every);
  gui.set_pacing({Pacing::fastest, 1, 1}).get();
  const QTransform t = fit_transform(gui.snapshot()->scene->map.bounds, QSizeF(1920, 1080));
  gui.start();
  const auto start = Clock::now();
  std::shared_ptr<const Snapshot> drawn;
  while (ms_since(start) < seconds * 1000) {
    const auto frame = Clock::now();
    if (auto snap = gui.snapshot(); snap != drawn) {
      drawn = std::move(snap);
      QPainter painter(&target);
      renderer.draw(painter, target.size(), *drawn, view, t);
    }
    std::this_thread::sleep_until(frame + std::chrono::microseconds(16'667));
  }
  gui.pause();
  gui.sync();
  const double in_gui = gui.snapshot()->time / (ms_since(start) / 1000);
  out << std::setprecision(2) << "simulation: headless " << headless << " simulated s per wall s, in the GUI (drawing each new snapshot, up to 60 FPS) "
      << in_gui << "; " << std::setprecision(0) << 100 * in_gui / headless << " % of headless\n";
  return 0;
}

}  // namespace salsa::gui
