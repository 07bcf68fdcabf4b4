// Replay in the desktop: a finished test opened from its folder shows at every playhead time what
// `salsa run` wrote for that time (positions, statuses, targets found, the inspected drone, the plots up
// to it); play, pause, speed and frame steps move the playhead; a second run plays beside it in step;
// a folder that is not a finished test is refused in one line shown in the window, which stays up and
// writes nothing into the folder.
#include "common.hpp"

#include <QLabel>
#include <QLineSeries>
#include <QPlainTextEdit>
#include <QSlider>
#include <QTemporaryDir>
#include <map>
#include <sstream>

#include "bench_replay.hpp"
#include "live_charts.hpp"
#include "main_window.hpp"
#include "replay_page.hpp"
#include "view.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

class GuiReplay : public QObject {
  Q_OBJECT
  QTemporaryDir dir_;
  QString a_, b_;  ///< groups-forest for 20 s, logged every 1 s and every 2 s
  std::unique_ptr<PluginHost> host_ = builtin_host();

  static QString run(const QString& out, const QString& log_interval) {
    const CliResult r = run_salsa({"run", q(source_dir() / "examples/groups-forest.json"), "--out", out, "--time", "20", "--log-interval", log_interval});
    if (r.exit_code != 0) qFatal("%s", qPrintable(r.err));
    return out + "/groups-forest";
  }

  /// The drones.csv rows of `test` logged at `time`, by id: x, y, status.
  static std::map<std::size_t, std::vector<std::string>> rows_at(const QString& test, double time) {
    const auto rows = rows_of(test + "/drones.csv");
    const std::size_t t = column(rows, "time"), id = column(rows, "id"), x = column(rows, "x"), y = column(rows, "y"), status = column(rows, "status");
    std::map<std::size_t, std::vector<std::string>> out;
    for (std::size_t k = 1; k < rows.size(); ++k)
      if (std::stod(rows[k][t]) == time) out[std::stoul(rows[k][id])] = {rows[k][x], rows[k][y], rows[k][status]};
    return out;
  }

  static std::size_t found_by(const QString& test, double time) {
    const auto rows = rows_of(test + "/targets.csv");
    const std::size_t c = column(rows, "found_time");
    std::size_t n = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) n += !rows[k][c].empty() && std::stod(rows[k][c]) <= time;
    return n;
  }

 private Q_SLOTS:
  void initTestCase() {
    a_ = run(dir_.path() + "/a", "1");
    b_ = run(dir_.path() + "/b", "2");
  }

  void each_time_shows_what_salsa_run_wrote() {
    ReplayPage page;
    page.resize(1200, 800);
    QCOMPARE(page.open(a_), std::string());
    QCOMPARE(page.runs(), std::size_t{1});
    QCOMPARE(page.player().end(), 20.0);
    QCOMPARE(page.timeline()->maximum(), 20000);
    const std::map<std::string, DroneStatus> code{{"flying", DroneStatus::flying}, {"camera_failed", DroneStatus::flying},
                                                 {"landed", DroneStatus::landed}, {"failed", DroneStatus::failed}};
    std::size_t stopped = 0, found_seen = 0;
    for (double t : {0.0, 3.5, 7.0, 12.25, 20.0}) {
      page.player().seek(t);
      const auto snap = page.shown(0);
      const double logged = std::floor(t);  // logged every second: the last row at or before t
      QCOMPARE(snap->time, logged);
      const auto rows = rows_at(a_, logged);
      QCOMPARE(rows.size(), snap->positions.size());
      for (const auto& [id, row] : rows) {
        QCOMPARE(snap->positions[id].x, std::stod(row[0]));
        QCOMPARE(snap->positions[id].y, std::stod(row[1]));
        QCOMPARE(snap->status_of(static_cast<std::uint32_t>(id)), code.at(row[2]));
        QCOMPARE(snap->camera_works(static_cast<std::uint32_t>(id)), row[2] != "camera_failed");
        stopped += row[2] == "failed" || row[2] == "landed";
      }
      QCOMPARE(snap->targets_found, found_by(a_, logged));
      found_seen = snap->targets_found;
      // The live plots up to the playhead: summary.csv's rows until then.
      const auto summary = rows_of(a_ + "/summary.csv");
      const std::size_t c_time = column(summary, "time"), c_found = column(summary, "fraction_found");
      int until = 0;
      for (std::size_t k = 1; k < summary.size(); ++k) until += std::stod(summary[k][c_time]) <= logged;
      QCOMPARE(page.charts()->series(0)->count(), until);
      QCOMPARE(page.charts()->series(0)->points().back().y(), 100 * std::stod(summary[static_cast<std::size_t>(until)][c_found]));
    }
    QVERIFY(stopped > 0);     // failed drones are shown failed (the test has failures)
    QVERIFY(found_seen > 0);  // targets turn found with time
    // The view draws the frame: two times look different.
    page.show();
    page.player().seek(2);
    const QImage early = page.view(0)->screenshot();
    page.player().seek(18);
    QVERIFY(page.view(0)->screenshot() != early);
  }

  void play_pause_speed_and_steps() {
    ReplayPage page;
    QCOMPARE(page.open(a_), std::string());
    Player& p = page.player();
    p.play();
    QVERIFY(p.playing());
    p.advance(2.5);
    QCOMPARE(p.time(), 2.5);
    QCOMPARE(page.shown(0)->time, 2.0);
    p.set_speed(4);
    p.advance(1);
    QCOMPARE(p.time(), 6.5);
    p.pause();
    p.advance(1);  // paused: stays
    QCOMPARE(p.time(), 6.5);
    p.step(1);
    QCOMPARE(p.time(), 7.0);
    p.step(-2);
    QCOMPARE(p.time(), 5.0);
    QCOMPARE(page.shown(0)->time, 5.0);
    p.play();
    p.advance(100);  // past the end: stops there
    QCOMPARE(p.time(), 20.0);
    QVERIFY(!p.playing());
    QCOMPARE(page.timeline()->value(), 20000);
    // The keys, with the view focused: Left and Right step a frame, Space plays and pauses.
    page.show();
    page.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&page));
    page.view(0)->setFocus();
    QTest::keyClick(page.view(0), Qt::Key_Left);
    QCOMPARE(p.time(), 19.0);
    QTest::keyClick(page.view(0), Qt::Key_Right);
    QCOMPARE(p.time(), 20.0);
    QTest::keyClick(page.view(0), Qt::Key_Space);  // at the end: from the start
    QVERIFY(p.playing());
    QCOMPARE(p.time(), 0.0);
    QTest::keyClick(page.view(0), Qt::Key_Space);
    QVERIFY(!p.playing());
    // The slider follows the playhead and drives it.
    page.timeline()->setValue(9300);
    QCOMPARE(p.time(), 9.3);
    QCOMPARE(page.shown(0)->time, 9.0);
  }

  void clicked_drone_shows_its_recorded_state() {
    ReplayPage page;
    QCOMPARE(page.open(a_), std::string());
    page.player().seek(10);
    page.select(4);
    const auto row = rows_at(a_, 10).at(4);
    const QString text = page.inspector()->toPlainText();
    QVERIFY2(text.startsWith("drone 4 of group "), qPrintable(text));
    QVERIFY2(text.contains("position [" + QString::number(std::round(std::stod(row[0]) * 100) / 100)), qPrintable(text));
    QVERIFY2(text.contains("neighbours ("), qPrintable(text));
    QVERIFY2(!text.contains("obstacle hits"), qPrintable(text));  // not recorded: not claimed to be none
    QVERIFY(page.shown(0)->selected);
    QCOMPARE(page.shown(0)->selected->id, 4u);
    page.player().seek(11);  // follows the playhead
    QCOMPARE(page.shown(0)->selected->position.x, std::stod(rows_at(a_, 11).at(4)[0]));
    page.select(std::nullopt);
    QVERIFY(page.inspector()->toPlainText().isEmpty());
  }

  void two_runs_side_by_side_in_step() {
    ReplayPage page;
    QCOMPARE(page.open(a_), std::string());
    QCOMPARE(page.compare(b_), std::string());
    QCOMPARE(page.runs(), std::size_t{2});
    QVERIFY(page.title(0).contains("groups-forest") && page.title(0).contains("every 1 s"));
    QVERIFY(page.title(1).contains("every 2 s"));
    page.player().seek(5.5);
    // One playhead: each shows its own last frame at or before it.
    QCOMPARE(page.shown(0)->time, 5.0);
    QCOMPARE(page.shown(1)->time, 4.0);
    const auto rows = rows_at(b_, 4);
    for (const auto& [id, row] : rows) QCOMPARE(page.shown(1)->positions[id].x, std::stod(row[0]));
    // The same seed and world: at a time both logged, both show the same swarm.
    page.player().seek(6);
    QCOMPARE(page.shown(0)->positions, page.shown(1)->positions);
    // Frame steps go through both runs' frames; the plots show both.
    page.player().step(-1);
    QCOMPARE(page.player().time(), 5.0);
    QCOMPARE(page.charts()->series(0, 0)->count(), 6);  // 0 … 5 s
    QCOMPARE(page.charts()->series(0, 1)->count(), 3);  // 0, 2, 4 s
    // Clicking selects the drone in both.
    page.select(2);
    QVERIFY(page.shown(0)->selected && page.shown(1)->selected);
    QCOMPARE(page.inspector()->toPlainText().count("drone 2"), 2);
    // Open starts over with one run, nothing selected.
    QCOMPARE(page.open(b_), std::string());
    QCOMPARE(page.runs(), std::size_t{1});
    QVERIFY(!page.shown(0)->selected);
    QCOMPARE(page.charts()->series(0, 1)->count(), 0);
  }

  void not_a_finished_test_is_refused_in_the_window() {
    MainWindow window(*host_);
    window.show();
    ReplayPage* page = window.replay_page();
    QCOMPARE(page->open(a_), std::string());
    const QString root = dir_.path() + "/a";  // the run's folder, not a test's
    const auto before = snapshot(root);
    for (const QString& bad : {root, dir_.path() + "/nowhere", a_ + "/drones.csv"}) {
      const std::string why = page->open(bad);
      QVERIFY2(!why.empty(), qPrintable(bad));
      QVERIFY2(why.find('\n') == std::string::npos, why.c_str());
      QCOMPARE(page->note()->text(), QString::fromStdString(why));
      QVERIFY(!page->note()->isHidden());
      QCOMPARE(window.status_text(), QString::fromStdString(why));
      QCOMPARE(page->runs(), std::size_t{1});  // what was open stays open
      QCOMPARE(page->compare(bad), why);
    }
    QCOMPARE(snapshot(root), before);  // nothing written into the folder read
    QVERIFY(window.isVisible());
    QCOMPARE(page->open(b_), std::string());  // and it goes on
    QVERIFY(page->note()->isHidden());
  }

  // Two runs side by side still fit a 1366 x 768 laptop screen.
  void side_by_side_fits_a_laptop_screen() {
    MainWindow window(*host_);
    window.show();
    QCOMPARE(window.replay_page()->open(a_), std::string());
    QCOMPARE(window.replay_page()->compare(b_), std::string());
    window.set_mode(MainWindow::Mode::replay);
    QCOMPARE(window.windowTitle(), QString("salsa — replay"));
    QApplication::processEvents();
    const QSize min = window.minimumSizeHint().expandedTo(window.minimumSize());
    QVERIFY2(min.width() <= 1366 && min.height() <= 720, qPrintable(QString("the window needs %1 x %2 px").arg(min.width()).arg(min.height())));
  }

  void benchmark_reports_seek_and_playback() {
    std::ostringstream out;
    QCOMPARE(bench_replay(a_.toStdString(), out, 20), 0);
    const QString report = QString::fromStdString(out.str());
    QVERIFY2(report.contains("recording: 18 drones, 21 frames over 20.00 s from drones.csv"), qPrintable(report));
    QVERIFY2(report.contains("trails of 31 frames"), qPrintable(report));  // 30 s at 1 s a frame
    QVERIFY2(report.contains(QRegularExpression("\nseek: 20 random times; [^\n]* max [0-9.]+ ms \\(budget 100 ms\\); CPU time mean [0-9.]+ ms, max [0-9.]+ ms\n")), qPrintable(report));
    QVERIFY2(report.contains(QRegularExpression("\nplayback: 21 consecutive frames; [^\n]* [0-9]+ FPS drawable \\(budget 60\\), [0-9]+ on its CPU time\n")), qPrintable(report));
    // A big swarm draws shorter trails (each frame redraws them all): 60,000 points at most.
    Recording big;
    big.drones = 10000;
    big.log_interval = 1;
    QCOMPARE(trail_frames(big), std::size_t{6});
    big.log_interval = 0.1;
    big.drones = 10;
    QCOMPARE(trail_frames(big), std::size_t{300});
    std::ostringstream bad;
    QCOMPARE(bench_replay((dir_.path() + "/a").toStdString(), bad, 20), 2);
  }
};

QTEST_MAIN(GuiReplay)
#include "gui_replay.moc"
