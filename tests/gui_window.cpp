// The sandbox window as a person uses it: sliders come from the behavior's declared schema, moving one
// changes the running simulation and is recorded, the drone count re-spawns, a bad file leaves
// everything as it was with the CLI's message, Space starts, and a saved session replays with salsa run.
#include "common.hpp"

#include <QAction>
#include <QLineSeries>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QSettings>
#include <QSlider>
#include <QSpinBox>
#include <QTemporaryDir>

#include "live_charts.hpp"
#include "main_window.hpp"
#include "param_panel.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

class GuiWindow : public QObject {
  Q_OBJECT
  std::unique_ptr<PluginHost> host_ = builtin_host();
  std::unique_ptr<MainWindow> window_;

  void settle() {
    window_->sandbox()->engine().sync();
    window_->sandbox()->poll();
  }

 private Q_SLOTS:
  void init() {
    QSettings().clear();  // each test starts from the first scene, not the last session's
    window_ = std::make_unique<MainWindow>(*host_);
    window_->resize(1400, 900);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    QVERIFY(window_->sandbox()->open_test(q(source_dir() / "examples/flocking-forest.json")).empty());
  }
  void cleanup() { window_.reset(); }

  void sliders_come_from_the_schema() {
    const Parameters& schema = host_->behavior("flocking").factory.parameters;
    ParamPanel* panel = window_->sandbox()->behavior_panel();
    QCOMPARE(panel->schema().size(), schema.size());
    for (const Parameter& p : schema) {
      QSlider* slider = panel->slider(p.name);
      QAbstractSpinBox* spin = panel->spin_box(p.name);
      QVERIFY2(slider && spin, p.name.c_str());
      QVERIFY(spin->toolTip().contains(QString::fromStdString(p.description)));
      QVERIFY(spin->toolTip().contains(QString::fromStdString(p.range())));
      if (p.is_integer()) QVERIFY(qobject_cast<QSpinBox*>(spin));
      else {
        auto* d = qobject_cast<QDoubleSpinBox*>(spin);
        QVERIFY(d);
        QCOMPARE(d->minimum(), p.min);
        QCOMPARE(d->maximum(), p.max);
      }
    }
    // The test file's value is shown (flocking-forest sets separation_distance 60).
    QCOMPARE(panel->value("separation_distance"), 60.0);
    // A whole-number parameter gets an integer box (pheromone avoidance's "directions").
    window_->sandbox()->behavior_box()->setCurrentText("pheromone_avoidance");
    QVERIFY(qobject_cast<QSpinBox*>(window_->sandbox()->behavior_panel()->spin_box("directions")));
  }

  void moving_a_slider_changes_the_live_parameter_and_is_recorded() {
    for (int i = 0; i < 20; ++i) window_->sandbox()->step();
    settle();
    auto* spin = qobject_cast<QDoubleSpinBox*>(window_->sandbox()->behavior_panel()->spin_box("cohesion_weight"));
    QVERIFY(spin);
    spin->setValue(2.5);  // as a user typing it
    settle();
    QCOMPARE(window_->sandbox()->engine().current_test()->groups[0].behavior.params.get("cohesion_weight"), 2.5);
    QSlider* slider = window_->sandbox()->behavior_panel()->slider("alignment_weight");
    slider->setValue(slider->maximum() / 2);  // as a user dragging it
    settle();
    const auto timeline = window_->sandbox()->engine().timeline();
    QCOMPARE(timeline.size(), std::size_t(2));
    QCOMPARE(timeline[0].key, std::string("behavior.params.cohesion_weight"));
    QCOMPARE(change_step(timeline[0].time, 1.0 / 60), std::uint64_t(20));
    QCOMPARE(timeline[1].key, std::string("behavior.params.alignment_weight"));
    QCOMPARE(window_->sandbox()->engine().current_test()->groups[0].behavior.params.get("alignment_weight"), timeline[1].value);
  }

  // A test's own timed changes play in the sandbox as in salsa run, and the controls follow them.
  void a_tests_timed_changes_play_and_the_controls_follow() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.path() + "/timed.json", R"({"name": "timed", "behavior": "flocking", "drones": 8, "seed": 2,
      "map": {"name": "forest", "params": {"size": 300}}, "time": 5,
      "changes": [{"time": 0.5, "set": {"drones": 14}}, {"time": 0.5, "set": {"drone.max_speed": 6}}]})"));
    SandboxPage& sandbox = *window_->sandbox();
    QVERIFY(sandbox.open_test(dir.path() + "/timed.json").empty());
    QVERIFY2(sandbox.last_message().contains("2 timed changes apply as it runs"), qPrintable(sandbox.last_message()));
    QCOMPARE(sandbox.drones_box()->value(), 8);
    for (int i = 0; i < 31; ++i) QCOMPARE(sandbox.engine().step_once().get(), std::string());  // past t = 0.5 s
    sandbox.poll();
    QCOMPARE(sandbox.engine().snapshot()->positions.size(), std::size_t(14));
    QCOMPARE(sandbox.drones_box()->value(), 14);
    QCOMPARE(sandbox.drone_panel()->value("max_speed"), 6.0);
    // Save as test keeps them: the saved file holds both changes.
    std::string why;
    const auto saved = sandbox.engine().as_test(&why);
    QVERIFY2(saved, why.c_str());
    QCOMPARE(saved->changes.size(), std::size_t(2));
  }

  void drone_count_respawns() {
    window_->sandbox()->drones_box()->setValue(45);
    settle();
    QCOMPARE(window_->sandbox()->engine().snapshot()->positions.size(), std::size_t(45));
    QCOMPARE(window_->sandbox()->engine().timeline().back().key, std::string("drones"));
  }

  void a_refused_change_puts_the_control_back() {
    // 60 m/s is more than radius / dt for the small drone: the core refuses it; the box shows 10 again.
    auto* speed = qobject_cast<QDoubleSpinBox*>(window_->sandbox()->drone_panel()->spin_box("max_speed"));
    speed->setValue(100);
    settle();
    QVERIFY2(window_->sandbox()->last_message().startsWith("drone.max_speed: 100 m/s"), qPrintable(window_->sandbox()->last_message()));
    QCOMPARE(speed->value(), 10.0);
    QCOMPARE(window_->sandbox()->engine().current_test()->groups[0].drone.max_speed, 10.0);
  }

  void clicking_a_drone_shows_its_state() {
    for (int i = 0; i < 30; ++i) window_->sandbox()->step();
    settle();
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->engine().snapshot()->step == 30, 5000);
    window_->sandbox()->view()->show_snapshot(window_->sandbox()->engine().snapshot());
    const auto snap = window_->sandbox()->engine().snapshot();
    const QPoint at = window_->sandbox()->view()->world_to_px().map(QPointF(snap->positions[7].x, snap->positions[7].y)).toPoint();
    QTest::mouseClick(window_->sandbox()->view(), Qt::LeftButton, {}, at);
    window_->sandbox()->engine().sync();
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->engine().snapshot()->selected.has_value(), 5000);
    const std::uint32_t id = window_->sandbox()->engine().snapshot()->selected->id;
    QVERIFY2(distance(snap->positions[id], snap->positions[7]) < 3, "the clicked drone, or one on top of it");
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->inspector_text().startsWith(QString("drone %1\nposition (").arg(id)), 5000);
    QVERIFY(window_->sandbox()->inspector_text().contains("neighbours ("));
  }

  void bad_files_keep_the_state() {
    for (int i = 0; i < 10; ++i) window_->sandbox()->step();
    settle();
    const auto before = window_->sandbox()->engine().snapshot();
    QTemporaryDir dir;
    write_file(dir.path() + "/bad-map.json", R"({"bounds": {"min": [0, 0], "max": [100, 100]}, "obstacles": [[[10, 10], [20, 10], [500, 20]]]})");
    std::string why = window_->sandbox()->open_map(dir.path() + "/bad-map.json");
    QVERIFY2(why.find("bad-map.json") != std::string::npos && why.find("obstacles[0][2]") != std::string::npos, why.c_str());
    QCOMPARE(window_->sandbox()->last_message(), QString::fromStdString(why));
    write_file(dir.path() + "/bad-test.json", R"({"behavior": "flocking", "drones": -3})");
    why = window_->sandbox()->open_test(dir.path() + "/bad-test.json");
    QVERIFY2(why.find("bad-test.json: drones: -3") != std::string::npos, why.c_str());
    settle();
    const auto after = window_->sandbox()->engine().snapshot();
    QCOMPARE(after->scene, before->scene);
    QCOMPARE(after->step, before->step);
    QCOMPARE(after->positions, before->positions);
    QCOMPARE(window_->sandbox()->behavior_box()->currentText(), QString("flocking"));
  }

  void space_starts_and_pauses() {
    window_->activateWindow();
    QTest::keyClick(window_.get(), Qt::Key_Space);
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->engine().snapshot()->state == RunState::running, 5000);
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->engine().snapshot()->time > 0.2, 20000);
    QTest::keyClick(window_.get(), Qt::Key_Space);
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->engine().snapshot()->state == RunState::paused, 5000);
    // The live plots got rows and drew them.
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->charts()->series(0)->count() >= 1, 5000);
  }

  // The window's "Save as test" writes a file that salsa run accepts and replays to the same state.
  void save_as_test_then_salsa_run() {
    for (int i = 0; i < 30; ++i) window_->sandbox()->step();
    settle();
    window_->sandbox()->drones_box()->setValue(12);
    settle();
    for (int i = 0; i < 30; ++i) window_->sandbox()->step();
    settle();
    QTemporaryDir dir;
    QCOMPARE(window_->sandbox()->save_test(dir.path() + "/tuned.json"), std::string());
    const auto snap = window_->sandbox()->engine().snapshot();
    const CliResult r = run_salsa({"run", "tuned.json", "--out", "out", "--no-plots", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QStringList rows = non_empty_lines(read_file(dir.path() + "/out/tuned/drones.csv")).filter(QRegularExpression("^1\\.0000,"));
    QCOMPARE(rows.size(), 12);
    for (std::size_t i = 0; i < 12; ++i)
      QCOMPARE(rows[static_cast<int>(i)], QString::asprintf("1.0000,%zu,%.4f,%.4f,%.4f,%.4f", i, snap->positions[i].x,
                                                            snap->positions[i].y, snap->velocities[i].x, snap->velocities[i].y));
  }
};

QTEST_MAIN(GuiWindow)
#include "gui_window.moc"
