#include "recorder.hpp"

#include <QDir>
#include <QFileInfo>

#include "video_writer.hpp"

namespace salsa::gui {

bool save_png(const QImage& image, const QString& path, QString* error) {
  if (image.save(path, "PNG")) return true;
  if (error) *error = path + ": cannot write the PNG (is the folder there and writable?)";
  return false;
}

Recorder::Recorder(Engine& engine, QString folder, double interval, QSize size, ViewOptions options,
                   std::optional<QTransform> world_to_px)
    : engine_(engine), folder_(std::move(folder)), interval_(interval), size_(size), options_(options), transform_(world_to_px) {}

Recorder::~Recorder() { stop(); }

void Recorder::start() {
  if (started_) return;
  if (!QDir().mkpath(folder_)) {
    error_ = folder_ + ": cannot create the folder";
    return;
  }
  started_ = true;
  // Runs on the engine's worker, which waits for it: no frame is skipped however slow the drawing.
  engine_.on_frame(interval_, [this](std::shared_ptr<const Snapshot> snap) {
    if (!error_.isEmpty()) return;
    const int n = frames_ + 1;
    const QString path = QDir(folder_).filePath(QString("frame_%1.png").arg(n, 5, 10, QChar('0')));
    QString why;
    if (!save_png(render_frame(*snap, options_, size_, transform_), path, &why)) {
      error_ = why;
      return;
    }
    frames_ = n;
  });
}

void Recorder::stop() {
  if (!started_) return;
  engine_.on_frame(0, nullptr);
  started_ = false;
}

QString Recorder::error() const { return error_; }

QString Recorder::make_video(QString* error) const {
  if (frames_ == 0) {
    if (error) *error = "no frames were recorded";
    return {};
  }
  const QString video = QDir(folder_).filePath("recording.mp4");
  VideoWriter writer;
  QString why;
  if (writer.open(video, size_, 30, &why)) {
    bool unreadable = false;
    for (int n = 1; n <= frames_ && !unreadable; ++n) {
      const QString path = QDir(folder_).filePath(QString("frame_%1.png").arg(n, 5, 10, QChar('0')));
      const QImage frame(path);
      if ((unreadable = frame.isNull())) why = path + ": cannot read the PNG";
      else if (!writer.write(frame)) break;  // ffmpeg stopped: finish says why
    }
    if (!unreadable && writer.finish(&why)) return video;
  }
  if (error) *error = why + "; the PNG frames are in " + folder_;
  return {};
}

}  // namespace salsa::gui
