#include "video_writer.hpp"

#include <QFile>
#include <QFileInfo>
#include <QStandardPaths>
#include <filesystem>
#include <system_error>

namespace salsa::gui {

VideoWriter::~VideoWriter() {
  if (!open_) return;
  ffmpeg_.kill();
  ffmpeg_.waitForFinished(5000);
  QFile::remove(partial_);
}

bool VideoWriter::open(const QString& file, QSize size, double fps, QString* error) {
  const QString ffmpeg = QStandardPaths::findExecutable("ffmpeg");
  if (ffmpeg.isEmpty()) {
    if (error) *error = "ffmpeg not found: install it (Debian, Ubuntu: `sudo apt install ffmpeg`; elsewhere: ffmpeg.org) to make " + file;
    return false;
  }
  file_ = file, partial_ = file + ".part", size_ = size;
  // A folder, or one that cannot be written to, is said here in the user's words, not in ffmpeg's.
  if (QFileInfo(file).isDir()) {
    if (error) *error = file + " is a folder (allowed: a file to write, e.g. run.mp4)";
    return false;
  }
  if (QFile partial(partial_); !partial.open(QIODevice::WriteOnly)) {
    if (error) *error = "cannot write " + file + " (" + partial.errorString() + ")";
    return false;
  }
  // -f mp4: the format is not guessed from the partial file's name.
  ffmpeg_.start(ffmpeg, {"-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s",
                         QString("%1x%2").arg(size.width()).arg(size.height()), "-r", QString::number(fps, 'g', 12), "-i", "-",
                         "-vf", "crop=trunc(iw/2)*2:trunc(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-f", "mp4", partial_});
  if (!ffmpeg_.waitForStarted(30000)) {
    if (error) *error = ffmpeg + ": did not start (" + ffmpeg_.errorString() + ")";
    QFile::remove(partial_);
    return false;
  }
  open_ = true;
  return true;
}

bool VideoWriter::write(const QImage& frame) {
  if (!open_ || ffmpeg_.state() != QProcess::Running) return false;
  const QImage rgb = frame.size() == size_ ? frame.convertToFormat(QImage::Format_RGB888)
                                           : frame.scaled(size_).convertToFormat(QImage::Format_RGB888);
  const qint64 row = qint64{size_.width()} * 3;  // a scan line may be padded: send each without it
  for (int y = 0; y < rgb.height(); ++y)
    if (ffmpeg_.write(reinterpret_cast<const char*>(rgb.constScanLine(y)), row) != row) return false;
  // Without an event loop QProcess only writes while waiting: hand the frame over before drawing the next.
  while (ffmpeg_.bytesToWrite() > 0)
    if (!ffmpeg_.waitForBytesWritten(-1)) return false;
  return true;
}

bool VideoWriter::finish(QString* error) {
  if (!open_) return false;
  open_ = false;
  ffmpeg_.closeWriteChannel();
  ffmpeg_.waitForFinished(-1);
  const bool ok = ffmpeg_.exitStatus() == QProcess::NormalExit && ffmpeg_.exitCode() == 0;
  std::error_code ec;
  if (ok) std::filesystem::rename(partial_.toStdString(), file_.toStdString(), ec);
  if (ok && !ec) return true;
  QFile::remove(partial_);
  if (error) {
    const QString said = QString::fromUtf8(ffmpeg_.readAllStandardError()).trimmed().section('\n', -1);
    *error = !ok ? file_ + ": ffmpeg failed: " + (said.isEmpty() ? QString("exit code %1").arg(ffmpeg_.exitCode()) : said)
                 : file_ + ": cannot write it (" + QString::fromStdString(ec.message()) + ")";
  }
  return false;
}

}  // namespace salsa::gui
