// salsa export --video: a finished test drawn into an MP4 without a display (no QT_QPA_PLATFORM, no
// DISPLAY): the frame count the documented rule gives, the size asked for, drones in their group's
// colour where drones.csv puts them; ffmpeg missing or failing is one line and leaves no file behind.
#include <QtTest>

#include <QImage>
#include <cmath>

#include "common.hpp"
#include "frame_renderer.hpp"
#include "salsa/core/replay/recording.hpp"

using namespace salsa;
using namespace salsa_test;

class TestExportVideo : public QObject {
  Q_OBJECT
  QTemporaryDir dir_;
  QString test_, video_;  ///< groups-forest run for 20 s; its video at 10 fps, 5 s of the run per second
  QString ffmpeg_, ffprobe_;

  /// What `program args` prints on stdout (the test fails if it does not succeed).
  static QByteArray output(const QString& program, const QStringList& args) {
    QProcess p;
    p.start(program, args);
    if (!p.waitForFinished(120000) || p.exitCode() != 0) qFatal("%s failed: %s", qPrintable(program), p.readAllStandardError().constData());
    return p.readAllStandardOutput();
  }

  static int distance(QColor a, QColor b) {
    return std::abs(a.red() - b.red()) + std::abs(a.green() - b.green()) + std::abs(a.blue() - b.blue());
  }

 private Q_SLOTS:
  void initTestCase() {
    // As on a server: no platform chosen and no display. salsa must choose the offscreen platform itself.
    for (const char* name : {"QT_QPA_PLATFORM", "DISPLAY", "WAYLAND_DISPLAY"}) qunsetenv(name);
    ffmpeg_ = QStandardPaths::findExecutable("ffmpeg"), ffprobe_ = QStandardPaths::findExecutable("ffprobe");
    if (ffmpeg_.isEmpty() || ffprobe_.isEmpty()) QSKIP("ffmpeg and ffprobe are not installed (scripts/setup.sh installs them)");
    const CliResult r = run_salsa({"run", q(source_dir() / "examples/groups-forest.json"), "--out", dir_.path() + "/out", "--time", "20"});
    QVERIFY2(r.exit_code == 0, describe(r));
    test_ = dir_.path() + "/out/groups-forest";
    video_ = dir_.path() + "/run.mp4";
    const CliResult v = run_salsa({"export", test_, "--video", video_, "--fps", "10", "--speed", "5", "--size", "640x480"});
    QVERIFY2(v.exit_code == 0, describe(v));
    QVERIFY2(v.out.contains("41 frames"), describe(v));
    QVERIFY(!QFile::exists(video_ + ".part"));
  }

  void frame_count_and_size() {
    // Frame k shows the run at k × 5 / 10 s, from 0 to 20 s: floor(20 × 10 / 5) + 1 = 41 frames.
    const QString probe = output(ffprobe_, {"-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                                            "stream=nb_read_frames,width,height,codec_name,pix_fmt", "-of", "csv=p=0", video_})
                              .trimmed();
    QCOMPARE(probe, QString("h264,640,480,yuv420p,41"));
  }

  void an_odd_size_loses_a_row_and_a_column() {
    const QString file = dir_.path() + "/odd.mp4";
    const CliResult r = run_salsa({"export", test_, "--video", file, "--size", "65x49", "--speed", "20"});
    QVERIFY2(r.exit_code == 0 && r.out.contains("31 frames of 64x48"), describe(r));  // floor(20 × 30 / 20) + 1
    QCOMPARE(output(ffprobe_, {"-v", "error", "-show_entries", "stream=width,height", "-of", "csv=p=0", file}).trimmed(), QByteArray("64,48"));
  }

  void drones_in_their_colours_where_the_run_put_them() {
    // Frame 20 shows the run at 10 s: each flying drone's centre is its group's colour (of two: blue,
    // orange), give or take the compression.
    const QString png = dir_.path() + "/frame20.png";
    output(ffmpeg_, {"-v", "error", "-y", "-i", video_, "-vf", "select=eq(n\\,20)", "-frames:v", "1", png});
    const QImage frame(png);
    QCOMPARE(frame.size(), QSize(640, 480));
    const Recording rec = load_recording(test_.toStdString());
    const QTransform to_px = gui::fit_transform(rec.map.bounds, QSizeF(640, 480));
    const std::size_t f = rec.frame_at(10);
    QCOMPARE(rec.times[f], 10.0);
    const QColor colours[] = {gui::group_colour(0, 2), gui::group_colour(1, 2)};
    std::size_t checked = 0, matched = 0;
    for (std::size_t id = 0; id < rec.drones; ++id) {
      if (rec.status(f, id) != 0) continue;
      const Vec2 p = rec.position(f, id);
      const QPoint px = to_px.map(QPointF(p.x, p.y)).toPoint();
      const std::size_t own = static_cast<std::size_t>(rec.at(*rec.column("group"), f, id)), other = 1 - own;
      ++checked;
      const QColor seen = frame.pixelColor(px);
      matched += distance(seen, colours[own]) < 90 && distance(seen, colours[own]) < distance(seen, colours[other]);
    }
    QVERIFY(checked >= 12);
    // Drones that overlap another group's hide part of themselves: nearly all, not all, must show.
    QVERIFY2(matched >= checked * 9 / 10, qPrintable(QString("%1 of %2 drones in their colour").arg(matched).arg(checked)));
    // And the same pixels at 0 s (frame 0) do not show them: the frame's time is the run's.
    const QString first = dir_.path() + "/frame0.png";
    output(ffmpeg_, {"-v", "error", "-y", "-i", video_, "-frames:v", "1", first});
    const QImage start(first);
    std::size_t still = 0;
    for (std::size_t id = 0; id < rec.drones; ++id) {
      const Vec2 p = rec.position(f, id), p0 = rec.position(0, id);
      if (std::hypot(p.x - p0.x, p.y - p0.y) < 20) continue;  // moved less than a few drones' widths
      const std::size_t own = static_cast<std::size_t>(rec.at(*rec.column("group"), f, id));
      still += distance(start.pixelColor(to_px.map(QPointF(p.x, p.y)).toPoint()), colours[own]) < 90;
    }
    QCOMPARE(still, std::size_t{0});
  }

  void ffmpeg_missing_is_one_line() {
    const QString file = dir_.path() + "/missing.mp4";
    const CliResult r = run_program(salsa_executable(), {"export", test_, "--video", file}, {}, {{"PATH", dir_.path() + "/nowhere"}});
    QCOMPARE(r.exit_code, 2);
    QCOMPARE(non_empty_lines(r.err).size(), 1);
    QVERIFY2(r.err.contains("ffmpeg not found") && r.err.contains("apt install ffmpeg"), describe(r));
    QVERIFY(!QFile::exists(file) && !QFile::exists(file + ".part"));
  }

  void an_unwritable_file_is_one_line() {
    for (const QString& file : {dir_.path() + "/no-such-folder/run.mp4", dir_.path()}) {
      const CliResult r = run_salsa({"export", test_, "--video", file});
      QCOMPARE(r.exit_code, 2);
      QCOMPARE(non_empty_lines(r.err).size(), 1);
      QVERIFY2(r.err.contains(file) && (r.err.contains("cannot write") || r.err.contains("is a folder")), describe(r));
    }
    QVERIFY(!QFile::exists(dir_.path() + ".part"));
  }

  void ffmpeg_failing_leaves_what_was_there() {
    // An ffmpeg that writes half a file and fails: its last line is the message, and the video
    // already at that name is left as it was.
    const QString bin = dir_.path() + "/broken-ffmpeg";
    QVERIFY(write_file(bin + "/ffmpeg", "#!/bin/sh\nfor a; do last=$a; done\necho half > \"$last\"\necho 'x264: out of luck' >&2\nexit 1\n"));
    QFile::setPermissions(bin + "/ffmpeg", QFile::ReadOwner | QFile::WriteOwner | QFile::ExeOwner);
    const QString file = dir_.path() + "/kept.mp4";
    QVERIFY(write_file(file, "an older video"));
    const CliResult r = run_program(salsa_executable(), {"export", test_, "--video", file}, {}, {{"PATH", bin}});
    QCOMPARE(r.exit_code, 1);
    QVERIFY2(!r.crashed, describe(r));
    QCOMPARE(non_empty_lines(r.err).size(), 1);
    QVERIFY2(r.err.contains("ffmpeg failed: x264: out of luck") && r.err.contains(file), describe(r));
    QCOMPARE(read_file(file), QByteArray("an older video"));
    QVERIFY(!QFile::exists(file + ".part"));
  }
};

QTEST_GUILESS_MAIN(TestExportVideo)
#include "test_export_video.moc"
