#pragma once
// Screenshots and recordings. A recording is PNG frames taken at a fixed interval of *simulated* time
// (the engine hands over a snapshot at exactly each multiple), so a video's timing does not depend on
// how fast the machine drew it; ffmpeg, when installed, turns them into an MP4.
#include <QImage>
#include <QSize>
#include <QString>
#include <QTransform>
#include <atomic>
#include <optional>

#include "engine.hpp"
#include "frame_renderer.hpp"

namespace salsa::gui {

/// Writes `image` as PNG; false with a one-line `error` naming the file.
bool save_png(const QImage& image, const QString& path, QString* error);

class Recorder {
 public:
  /// Frames of `size` px drawn with `options` and `world_to_px` (fit to the map when nullopt) into
  /// `folder`/frame_00001.png, … every `interval` s of simulated time.
  Recorder(Engine& engine, QString folder, double interval, QSize size, ViewOptions options,
           std::optional<QTransform> world_to_px = std::nullopt);
  ~Recorder();
  void start();
  void stop();
  int frames() const { return frames_; }
  QString error() const;  ///< the first write error, if any (recording stops at it)
  /// Turns the frames into `folder`/recording.mp4 with ffmpeg (30 frames per second of video); the
  /// file's path, or "" with `error` saying why (ffmpeg missing: how to get it).
  QString make_video(QString* error) const;

 private:
  Engine& engine_;
  QString folder_;
  double interval_;
  QSize size_;
  ViewOptions options_;
  std::optional<QTransform> transform_;
  std::atomic<int> frames_{0};
  QString error_;
  bool started_ = false;
};

}  // namespace salsa::gui
