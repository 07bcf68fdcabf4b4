// The sandbox view: a fixed scene draws like its golden image (antialiasing aside), clicking a drone
// selects it, the static layer is cached, moving targets are drawn where they are, and a recording holds
// one frame per interval of simulated time.
#include "common.hpp"

#include <QDir>
#include <QFileInfo>
#include <QStandardPaths>
#include <QPainter>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <cmath>

#include "recorder.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "view.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

/// A small fixed scene: walls, a polygon, a hollow outline, a line, targets found and not, drones
/// with trails, a heat map, a selected drone with neighbours and a ray hit.
std::shared_ptr<Snapshot> fixed_scene() {
  auto scene = std::make_shared<Scene>();
  scene->map.bounds = {{0, 0}, {200, 150}};
  scene->map.spawn = {100, 75};
  scene->bases = {{100, 75}};
  scene->map.obstacles = {{{30, 30}, {60, 30}, {60, 50}, {30, 50}}, {{140, 100}, {170, 95}, {160, 130}}};
  scene->map.hollow = {{{90, 110}, {120, 110}, {120, 135}, {90, 135}}};
  scene->map.lines = {{{20, 120}, {70, 140}}};
  scene->target_radius = 2;
  auto snap = std::make_shared<Snapshot>();
  for (int i = 0; i < 40; ++i) scene->targets.push_back({10.0 + 4.5 * i, 10.0 + (i % 5) * 3});
  snap->found.assign(40, 0);
  for (int i = 0; i < 40; i += 3) snap->found[static_cast<std::size_t>(i)] = 1;
  snap->targets_found = 14;
  snap->scene = scene;
  GroupLook group{"swarm", {}};
  group.drone.radius = 2;
  group.drone.camera_range = 10;
  group.drone.detection_range = 40;
  snap->groups = {group};
  snap->positions = {{100, 75}, {110, 80}, {80, 70}, {180, 20}};
  snap->velocities = {{5, 0}, {0, 5}, {-3, -3}, {0, 0}};
  snap->trail_length = 4;
  auto trails = std::make_shared<std::vector<Vec2>>();
  for (const Vec2 p : snap->positions)
    for (int k = 0; k < 4; ++k) trails->push_back(k == 0 ? Vec2{std::nan(""), 0} : p - Vec2{8.0 * (4 - k), 4.0 * (4 - k)});
  snap->trails = trails;
  auto heat = std::make_shared<HeatMap>();
  heat->origin = {0, 0};
  heat->cell = 25;
  heat->cols = 8;
  heat->rows = 6;
  for (int i = 0; i < 48; ++i) heat->values.push_back(i == 19 ? 100.f : static_cast<float>(i % 7) * 5);
  snap->heat = heat;
  Inspection in;
  in.id = 0;
  in.position = snap->positions[0];
  in.neighbours = {1, 2};
  in.hits = {ObstacleHit{{60, 45}, 40.3}};
  snap->selected = in;
  return snap;
}

ViewOptions all_on() {
  ViewOptions o;
  o.camera_range = o.heat_map = true;
  return o;
}

/// Pixels whose channels differ by more than 64: antialiasing moves a few, a real change many.
double differing(const QImage& a, const QImage& b) {
  const QImage x = a.convertToFormat(QImage::Format_ARGB32), y = b.convertToFormat(QImage::Format_ARGB32);
  std::size_t bad = 0;
  for (int r = 0; r < x.height(); ++r)
    for (int c = 0; c < x.width(); ++c) {
      const QRgb p = x.pixel(c, r), q = y.pixel(c, r);
      if (std::abs(qRed(p) - qRed(q)) > 64 || std::abs(qGreen(p) - qGreen(q)) > 64 || std::abs(qBlue(p) - qBlue(q)) > 64) ++bad;
    }
  return static_cast<double>(bad) / (x.width() * x.height());
}

}  // namespace

class GuiView : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  void golden_image() {
    const QImage image = render_frame(*fixed_scene(), all_on(), QSize(400, 300));
    const QString golden = q(source_dir() / "tests/data/gui/view-golden.png");
    if (qEnvironmentVariableIsSet("SALSA_UPDATE_GOLDEN")) QVERIFY(image.save(golden));
    const QImage want(golden);
    QVERIFY2(!want.isNull(), qPrintable(golden + " is missing: run gui_view with SALSA_UPDATE_GOLDEN=1 to draw it, look at it, commit it"));
    QCOMPARE(image.size(), want.size());
    const double off = differing(image, want);
    if (off > 0.005) image.save(QDir::temp().filePath("view-actual.png"));
    QVERIFY2(off <= 0.005, qPrintable(QString("%1 % of pixels differ from %2 (this run's image: %3)")
                                          .arg(100 * off).arg(golden, QDir::temp().filePath("view-actual.png"))));
    // And the check can fail: the same scene without its found targets is another picture.
    auto other = fixed_scene();
    other->found.assign(40, 0);
    QVERIFY(differing(render_frame(*other, all_on(), QSize(400, 300)), want) > 0.001);
  }

  void clicking_a_drone_selects_it() {
    SwarmView view;
    view.resize(400, 300);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    auto snap = fixed_scene();
    view.show_snapshot(snap);
    QSignalSpy clicked(&view, &SwarmView::drone_clicked);
    const QPoint on_drone = view.world_to_px().map(QPointF(110, 80)).toPoint();
    QTest::mouseClick(&view, Qt::LeftButton, {}, on_drone);
    QCOMPARE(clicked.size(), 1);
    QCOMPARE(clicked[0][0].value<std::optional<std::uint32_t>>(), std::optional<std::uint32_t>(1));
    const QPoint empty = view.world_to_px().map(QPointF(150, 40)).toPoint();
    QTest::mouseClick(&view, Qt::LeftButton, {}, empty);
    QCOMPARE(clicked.size(), 2);
    QCOMPARE(clicked[1][0].value<std::optional<std::uint32_t>>(), std::optional<std::uint32_t>());
    // A drag pans instead of selecting.
    const QTransform before = view.world_to_px();
    QTest::mousePress(&view, Qt::LeftButton, {}, on_drone);
    QTest::mouseMove(&view, on_drone + QPoint(40, 10));
    QTest::mouseRelease(&view, Qt::LeftButton, {}, on_drone + QPoint(40, 10));
    QCOMPARE(clicked.size(), 2);
    QVERIFY(view.world_to_px() != before);
  }

  void static_layer_is_cached() {
    FrameRenderer renderer;
    QImage target(400, 300, QImage::Format_ARGB32_Premultiplied);
    auto snap = fixed_scene();
    const QTransform t = fit_transform(snap->scene->map.bounds, QSizeF(400, 300));
    auto draw = [&](const Snapshot& s, const QTransform& tr) {
      QPainter p(&target);
      renderer.draw(p, target.size(), s, all_on(), tr);
    };
    draw(*snap, t);
    QCOMPARE(renderer.static_redraws(), std::size_t(1));
    auto moved = std::make_shared<Snapshot>(*snap);  // drones move: no redraw
    for (Vec2& p : moved->positions) p += Vec2{1, 1};
    draw(*moved, t);
    QCOMPARE(renderer.static_redraws(), std::size_t(1));
    moved->found_version = snap->found_version + 1;  // a target found: stamped over the layer
    moved->found[1] = 1;
    draw(*moved, t);
    QCOMPARE(renderer.static_redraws(), std::size_t(1));
    QCOMPARE(renderer.found_updates(), std::size_t(1));
    // ... which then shows what a whole redraw would.
    QVERIFY(differing(target, render_frame(*moved, all_on(), QSize(400, 300), t)) < 0.001);
    draw(*moved, t * QTransform::fromScale(1.25, 1.25));  // zoom: redraw
    QCOMPARE(renderer.static_redraws(), std::size_t(2));
    auto heat = std::make_shared<Snapshot>(*moved);  // a new heat map, shown: redraw
    heat->heat = std::make_shared<HeatMap>(*moved->heat);
    draw(*heat, t);
    QCOMPARE(renderer.static_redraws(), std::size_t(3));
  }

  // Moving targets (Snapshot::targets) are drawn where the snapshot says, frame after frame, not where
  // the scene placed them, and without redrawing the static layer.
  void moving_targets_are_drawn_where_they_are() {
    auto scene = std::make_shared<Scene>();
    scene->map.bounds = {{0, 0}, {200, 150}};
    scene->map.spawn = {100, 75};
    scene->target_radius = 5;
    scene->targets = {{40, 40}, {160, 110}};  // where they started
    auto snap = std::make_shared<Snapshot>();
    snap->scene = scene;
    snap->found = {1, 0};
    snap->targets = {{60, 100}, {140, 30}};  // where they are now
    ViewOptions options;
    options.trails = false;
    const QSize size(400, 300);
    const QTransform t = fit_transform(scene->map.bounds, QSizeF(size));
    auto colour_at = [&](const QImage& image, Vec2 p) { return QColor(image.pixel(t.map(QPointF(p.x, p.y)).toPoint())); };
    const QColor found(0x2e, 0x9e, 0x48), unfound(0x9a, 0x9a, 0x9a);
    FrameRenderer renderer;
    QImage frame(size, QImage::Format_ARGB32_Premultiplied);
    for (int k = 0; k < 2; ++k) {
      {
        QPainter p(&frame);
        renderer.draw(p, size, *snap, options, t);
      }
      for (const QImage& image : {frame, render_frame(*snap, options, size, t)}) {
        QCOMPARE(colour_at(image, snap->targets[0]), found);
        QCOMPARE(colour_at(image, snap->targets[1]), unfound);
        for (const Vec2 start : scene->targets) QCOMPARE(colour_at(image, start), QColor(0xf4, 0xf1, 0xea));  // the map's background
      }
      auto next = std::make_shared<Snapshot>(*snap);  // they walk on
      for (Vec2& p : next->targets) p += Vec2{15, -10};
      snap = next;
    }
    QCOMPARE(renderer.static_redraws(), std::size_t(1));
  }

  // One frame per 0.25 s of simulated time, each of the asked size.
  void recording_has_a_frame_per_interval() {
    auto host = builtin_host();
    Engine engine(*host);
    const TestSpec t = parse_test(R"({"behavior": "random_walk", "drones": 5, "map": {"name": "empty", "params": {"size": 200}}, "seed": 2})",
                                  "rec", *host);
    QCOMPARE(engine.load(t).get(), std::string());
    QTemporaryDir dir;
    Recorder recorder(engine, dir.path() + "/frames", 0.25, QSize(160, 120), ViewOptions{});
    recorder.start();
    for (int i = 0; i < 130; ++i) QCOMPARE(engine.step_once().get(), std::string());  // 130 steps = 2.1667 s
    recorder.stop();
    QVERIFY2(recorder.error().isEmpty(), qPrintable(recorder.error()));
    const QStringList frames = QDir(dir.path() + "/frames").entryList({"frame_*.png"}, QDir::Files, QDir::Name);
    QCOMPARE(frames.size(), 8);  // t = 0.25, 0.5, ..., 2.0
    QCOMPARE(recorder.frames(), 8);
    QCOMPARE(frames.front(), QString("frame_00001.png"));
    for (const QString& f : frames) QCOMPARE(QImage(dir.path() + "/frames/" + f).size(), QSize(160, 120));
    // Frames stop with the recording.
    QCOMPARE(engine.step_once().get(), std::string());
    for (int i = 0; i < 30; ++i) QCOMPARE(engine.step_once().get(), std::string());
    QCOMPARE(QDir(dir.path() + "/frames").entryList({"frame_*.png"}, QDir::Files).size(), 8);
    // The MP4: made by ffmpeg when it is installed; else the message says how to get it.
    QString why;
    const QString video = recorder.make_video(&why);
    if (QStandardPaths::findExecutable("ffmpeg").isEmpty()) {
      QVERIFY(video.isEmpty());
      QVERIFY2(why.contains("apt install ffmpeg") && why.contains(dir.path() + "/frames"), qPrintable(why));
    } else {
      QVERIFY2(!video.isEmpty(), qPrintable(why));
      QVERIFY(QFileInfo(video).size() > 1000);
      QVERIFY(!QFile::exists(video + ".part"));
      const QString ffprobe = QStandardPaths::findExecutable("ffprobe");
      if (!ffprobe.isEmpty()) {  // a video frame per PNG frame, the PNGs' size
        QProcess probe;
        probe.start(ffprobe, {"-v", "error", "-count_frames", "-show_entries", "stream=nb_read_frames,width,height", "-of", "csv=p=0", video});
        QVERIFY(probe.waitForFinished(60000));
        QCOMPARE(QString::fromUtf8(probe.readAllStandardOutput()).trimmed(), QString("160,120,8"));
      }
    }
  }
};

QTEST_MAIN(GuiView)
#include "gui_view.moc"
