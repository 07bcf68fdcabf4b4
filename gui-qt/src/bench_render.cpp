// Frame times of the sandbox view for the issue's scene (1,000 drones, 50,000 targets, trails on) at
// 1920×1080, drawn on the raster engine exactly as the window draws (FrameRenderer), while the engine
// runs; then the simulation's speed with the GUI drawing at 60 FPS against the same test headless.
#include "bench_render.hpp"

#include <QImage>
#include <QPainter>
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <numeric>
#include <thread>
#include <vector>

#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "view.hpp"

namespace salsa::gui {
namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// The forest-health scale: 2 km × 2 km, 50,000 trees, 1,000 drones.
constexpr const char* scene_test = R"({"name": "bench-render", "behavior": "random_walk", "drones": 1000,
  "map": {"name": "empty", "params": {"size": 2000}}, "targets": {"kind": "tree", "count": 50000}, "time": 1000000, "seed": 1})";
}  // namespace

int bench_render(const PluginHost& host, std::ostream& out, int frames) {
  out << "salsa-gui --bench-render --frames " << frames << "\n";
  const TestSpec test = parse_test(scene_test, "bench-render", host);
  out << "scene: 1,000 drones (random_walk), 50,000 trees on a 2000 m x 2000 m map, trails of 64 samples, 1920x1080, raster\n";

  // 1. Frame times while the engine runs in real time (as a user watches it).
  Engine engine(host);
  if (const std::string why = engine.load(test).get(); !why.empty()) {
    out << "salsa-gui: " << why << "\n";
    return 1;
  }
  engine.set_trails(64, 6);
  engine.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // trails filled in a little
  QImage target(1920, 1080, QImage::Format_ARGB32_Premultiplied);
  FrameRenderer renderer;
  ViewOptions options;
  options.trails = true;
  std::vector<double> times;
  const auto snap0 = engine.snapshot();
  const QTransform t = fit_transform(snap0->scene->map.bounds, QSizeF(1920, 1080));
  for (int i = 0; i < frames; ++i) {
    const auto snap = engine.snapshot();
    const auto start = Clock::now();
    QPainter painter(&target);
    renderer.draw(painter, target.size(), *snap, options, t);
    painter.end();
    times.push_back(ms_since(start));
    std::this_thread::sleep_until(start + std::chrono::microseconds(16'667));
  }
  engine.pause();
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  const double mean = std::accumulate(times.begin(), times.end(), 0.0) / static_cast<double>(times.size());
  const auto at = [&](double q) { return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * static_cast<double>(sorted.size())))]; };
  out << std::fixed << std::setprecision(2);
  out << "frames: " << frames << "; frame time mean " << mean << " ms, median " << at(0.5) << " ms, p95 " << at(0.95)
      << " ms, max " << sorted.back() << " ms; " << std::setprecision(0) << 1000 / mean << " FPS drawable; static layer drawn "
      << renderer.static_redraws() << " times\n";

  // 2. Simulation speed: the engine flat out while frames are drawn at 60 FPS, against headless.
  const double seconds = 5;
  auto steps_per_second_headless = [&] {
    Simulation sim(make_setup(test, host, static_cast<int>(std::max(1u, std::thread::hardware_concurrency() - 1))));
    const auto start = Clock::now();
    std::size_t steps = 0;
    while (ms_since(start) < seconds * 1000) sim.step(), ++steps;
    return sim.time() / (ms_since(start) / 1000);
  };
  const double headless = steps_per_second_headless();
  Engine gui(host);
  gui.load(test).get();
  gui.set_trails(64, 6);
  gui.set_pacing({Pacing::fastest, 1, 1}).get();
  gui.start();
  const auto start = Clock::now();
  while (ms_since(start) < seconds * 1000) {
    const auto frame = Clock::now();
    const auto snap = gui.snapshot();
    QPainter painter(&target);
    renderer.draw(painter, target.size(), *snap, options, t);
    painter.end();
    std::this_thread::sleep_until(frame + std::chrono::microseconds(16'667));
  }
  gui.pause();
  gui.sync();
  const double in_gui = gui.snapshot()->time / (ms_since(start) / 1000);
  out << std::setprecision(2) << "simulation: headless " << headless << " simulated s per wall s, in the GUI (drawing at 60 FPS) "
      << in_gui << "; " << std::setprecision(0) << 100 * in_gui / headless << " % of headless\n";
  return 0;
}

}  // namespace salsa::gui
