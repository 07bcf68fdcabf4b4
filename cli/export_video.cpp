// salsa export --video: the run drawn as the desktop draws it (gui-qt/frame/'s renderer, on the offscreen
// platform: no display needed) and piped to ffmpeg. Frame k shows the run at k × speed / fps seconds
// (the last recorded frame at or before it), from 0 to the last recorded time: floor(T × fps / speed) + 1
// frames for a run recorded until T.
#include "export.hpp"

#include <cmath>
#include <iostream>
#include <stdexcept>

#include "salsa/core/files/input_error.hpp"

#ifdef SALSA_WITH_VIDEO
#include <QFont>
#include <QFontMetrics>
#include <QPainter>

#include "frame_renderer.hpp"
#include "offscreen.hpp"
#include "recorded_frame.hpp"
#include "video_writer.hpp"
#endif

namespace salsa::cli {

std::size_t video_frames(double duration, const VideoOptions& options) {
  // The tolerance keeps an exact product (20 s × 10 fps / 5) from rounding down to one frame fewer.
  return static_cast<std::size_t>(std::floor(duration * options.fps / options.speed + 1e-9)) + 1;
}

#ifdef SALSA_WITH_VIDEO

namespace {

/// The test's name, time and targets found, at the bottom left (the desktop shows them beside its view).
void draw_caption(QPainter& painter, QSize size, const gui::Snapshot& snap, std::size_t targets) {
  QFont font = painter.font();
  font.setPixelSize(std::max(12, size.height() / 40));
  painter.setFont(font);
  const QString text = QString("%1   t = %2 s   found %3 / %4")
                           .arg(QString::fromStdString(snap.test_name))
                           .arg(snap.time, 0, 'f', 1)
                           .arg(snap.targets_found)
                           .arg(targets);
  const QFontMetrics metrics(font);
  const QRectF box(8, size.height() - metrics.height() - 16, metrics.horizontalAdvance(text) + 16, metrics.height() + 8);
  painter.setPen(QPen(QColor(0, 0, 0, 60), 1));
  painter.setBrush(QColor(255, 255, 255, 215));
  painter.drawRoundedRect(box, 4, 4);
  painter.setPen(Qt::black);
  painter.drawText(box, Qt::AlignCenter, text);
}

}  // namespace

void export_video(const Recording& recording, const std::filesystem::path& file, const VideoOptions& options) {
  if (!gui::ensure_gui_application()) throw std::logic_error("--video: this process cannot draw text (a QCoreApplication without a GUI)");
  const QSize size(options.width, options.height);
  const QString name = QString::fromStdString(file.string());
  gui::VideoWriter writer;
  QString error;
  if (!writer.open(name, size, options.fps, &error)) throw InputError("--video: " + error.toStdString());

  // Trails as long as the desktop's (64 samples, one every 6 steps), in recorded frames.
  const double span = 64 * 6 * recording.dt;
  const auto trail = recording.log_interval > 0 ? static_cast<std::size_t>(std::max(2.0, std::round(span / recording.log_interval))) : 2;
  const auto scene = gui::scene_of(recording);
  const QTransform world_to_px = gui::fit_transform(recording.map.bounds, QSizeF(size));
  const double end = recording.times.empty() ? 0 : recording.times.back();
  const std::size_t frames = video_frames(end, options);
  gui::FrameRenderer renderer;
  QImage image(size, QImage::Format_ARGB32_Premultiplied);
  bool sent = true;
  for (std::size_t k = 0; k < frames && sent; ++k) {
    const double t = static_cast<double>(k) * options.speed / options.fps;
    const gui::Snapshot snap = gui::recorded_snapshot(recording, scene, recording.frame_at(t * (1 + 1e-12)), trail);
    {
      QPainter painter(&image);
      renderer.draw(painter, size, snap, gui::ViewOptions{}, world_to_px);
      draw_caption(painter, size, snap, recording.targets.size());
    }
    sent = writer.write(image);  // false: ffmpeg stopped, and finish says why
  }
  if (!writer.finish(&error)) throw std::runtime_error("--video: " + error.toStdString());
  std::cout << "wrote " << file.string() << ": " << frames << " frames of " << writer.video_size().width() << "x" << writer.video_size().height() << " at "
            << options.fps << " fps, " << options.speed << " s of the run per second\n";
}

#else

void export_video(const Recording&, const std::filesystem::path& file, const VideoOptions&) {
  throw InputError("--video: " + file.string() + ": this salsa was built without Qt 6 Gui, which draws the frames (rebuild with qt6-base-dev installed)");
}

#endif

}  // namespace salsa::cli
