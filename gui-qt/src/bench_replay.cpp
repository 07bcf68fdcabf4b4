#include "bench_replay.hpp"

#include <QImage>
#include <QPainter>
#include <chrono>
#include <iomanip>
#include <random>
#include <vector>

#include "bench_render.hpp"
#include "frame_renderer.hpp"
#include "recorded_frame.hpp"
#include "replay_page.hpp"
#include "salsa/core/files/input_error.hpp"

namespace salsa::gui {
namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }
}  // namespace

int bench_replay(const std::filesystem::path& folder, std::ostream& out, int seeks) {
  out << "salsa-gui --bench-replay " << folder.string() << "\n";
  const auto start = Clock::now();
  Recording rec;
  try {
    rec = load_recording(folder);
  } catch (const InputError& e) {
    out << "salsa-gui: " << e.what() << "\n";
    return 2;
  }
  const double load_ms = ms_since(start);
  if (rec.frames() == 0) {
    out << "salsa-gui: " << folder.string() << ": no frames to replay\n";
    return 2;
  }
  const std::size_t trail = trail_frames(rec);
  out << std::fixed << std::setprecision(2) << "recording: " << rec.drones << " drones, " << rec.frames() << " frames over "
      << rec.times.back() << " s from " << rec.source.filename().string() << ", loaded in " << load_ms / 1000
      << " s; trails of " << trail << " frames, 1920x1080, raster\n";

  const auto scene = scene_of(rec);
  QImage target(1920, 1080, QImage::Format_ARGB32_Premultiplied);
  const QTransform t = fit_transform(rec.map.bounds, QSizeF(target.size()));
  ViewOptions view;
  FrameRenderer renderer;
  // One frame as a view shows it: the snapshot made, then drawn over the cached static layer.
  std::vector<double> cpu;
  auto show = [&](std::size_t frame, std::vector<double>& made, std::vector<double>& total) {
    const auto begin = Clock::now();
    const double cpu_begin = thread_cpu_ms();
    const Snapshot snap = recorded_snapshot(rec, scene, frame, trail);
    made.push_back(ms_since(begin));
    QPainter painter(&target);
    renderer.draw(painter, target.size(), snap, view, t);
    painter.end();
    total.push_back(ms_since(begin));
    cpu.push_back(thread_cpu_ms() - cpu_begin);
  };
  std::vector<double> made, total;
  show(0, made, total);  // the static layer, drawn once as on opening
  made.clear(), total.clear(), cpu.clear();

  std::mt19937 random(1);
  std::uniform_real_distribution<double> when(0, rec.times.back());
  for (int i = 0; i < seeks; ++i) show(rec.frame_at(when(random)), made, total);
  const BenchStats m = bench_stats(made), s = bench_stats(total), c = bench_stats(cpu);
  out << "seek: " << seeks << " random times; frame made in mean " << m.mean << " ms, max " << m.max << " ms; made and drawn in mean "
      << s.mean << " ms, p95 " << s.p95 << " ms, max " << s.max << " ms (budget 100 ms); CPU time mean " << c.mean << " ms, max " << c.max << " ms\n";

  made.clear(), total.clear(), cpu.clear();
  const std::size_t frames = std::min<std::size_t>(rec.frames(), 600);
  for (std::size_t f = 0; f < frames; ++f) show(f, made, total);
  const BenchStats pm = bench_stats(made), p = bench_stats(total), pc = bench_stats(cpu);
  out << "playback: " << frames << " consecutive frames; made in mean " << pm.mean << " ms, made and drawn in mean " << p.mean << " ms, p95 "
      << p.p95 << " ms, max " << p.max << " ms; CPU time mean " << pc.mean << " ms; " << std::setprecision(0) << 1000 / p.mean
      << " FPS drawable (budget 60), " << 1000 / pc.mean << " on its CPU time\n";
  return 0;
}

}  // namespace salsa::gui
