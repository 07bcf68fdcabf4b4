#pragma once
// Frames into an MP4 with ffmpeg (H.264, yuv420p: what players and browsers open), piped in as raw RGB:
// the desktop's recordings and salsa export --video. The video is written beside its name as
// NAME.part and renamed when ffmpeg has finished, so a failed or interrupted encoding leaves no
// half-written file under the name asked for.
#include <QImage>
#include <QProcess>
#include <QSize>
#include <QString>

namespace salsa::gui {

class VideoWriter {
 public:
  VideoWriter() = default;
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;
  ~VideoWriter();  ///< unfinished: stops ffmpeg and removes the partial file

  /// Starts ffmpeg on `file`, `size` px frames at `fps` per second. An odd width or height loses its
  /// last column or row (H.264's colour planes are half size). False with a one-line `error`: ffmpeg
  /// not installed (and how to get it), `file` a folder or not writable, or ffmpeg did not start.
  bool open(const QString& file, QSize size, double fps, QString* error);
  /// Sends one frame (drawn at the size given to open). False when ffmpeg has stopped: finish says why.
  bool write(const QImage& frame);
  /// Ends the video and waits for ffmpeg; false with `error` ending in ffmpeg's last line, and no file.
  bool finish(QString* error);
  /// The video's frame size: the size given to open, each side rounded down to even.
  QSize video_size() const { return {size_.width() / 2 * 2, size_.height() / 2 * 2}; }

 private:
  QProcess ffmpeg_;
  QString file_, partial_;
  QSize size_;
  bool open_ = false;
};

}  // namespace salsa::gui
