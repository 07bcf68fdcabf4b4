// The sandbox window as a person uses it: sliders come from the behavior's declared schema, moving one
// changes the running simulation and is recorded, the drone count re-spawns, a bad file leaves
// everything as it was with the CLI's message, Space starts, and a saved session replays with salsa run.
#include "common.hpp"

#include <QAction>
#include <QChartView>
#include <QGraphicsTextItem>
#include <QLineSeries>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QSettings>
#include <QSlider>
#include <QSpinBox>
#include <QTemporaryDir>
#include <cmath>
#include <QLabel>
#include <QGroupBox>
#include <QMessageBox>
#include <QPushButton>
#include <QScrollArea>
#include <QScrollBar>
#include <QTimer>

#include "live_charts.hpp"
#include "main_window.hpp"
#include "number_field.hpp"
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
      NumberField* spin = panel->spin_box(p.name);
      QVERIFY2(slider && spin, p.name.c_str());
      QVERIFY(spin->toolTip().contains(QString::fromStdString(p.description)));
      QVERIFY(spin->toolTip().contains(QString::fromStdString(p.range())));
      QCOMPARE(spin->spec().min, p.min);
      QCOMPARE(spin->spec().max, p.max);
      QCOMPARE(spin->spec().is_integer(), p.is_integer());
    }
    // The test file's value is shown (flocking-forest sets separation_distance 60).
    QCOMPARE(panel->value("separation_distance"), 60.0);
    // A whole-number parameter gets an integer box (pheromone avoidance's "directions").
    window_->sandbox()->behavior_box()->setCurrentText("pheromone_avoidance");
    QVERIFY(window_->sandbox()->behavior_panel()->spin_box("directions")->spec().is_integer());
  }

  void moving_a_slider_changes_the_live_parameter_and_is_recorded() {
    for (int i = 0; i < 20; ++i) window_->sandbox()->step();
    settle();
    auto* spin = window_->sandbox()->behavior_panel()->spin_box("cohesion_weight");
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
    QCOMPARE(sandbox.drones_box()->value(), 8.0);
    for (int i = 0; i < 31; ++i) QCOMPARE(sandbox.engine().step_once().get(), std::string());  // past t = 0.5 s
    sandbox.poll();
    QCOMPARE(sandbox.engine().snapshot()->positions.size(), std::size_t(14));
    QCOMPARE(sandbox.drones_box()->value(), 14.0);
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
    auto* speed = window_->sandbox()->drone_panel()->spin_box("max_speed");
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
    // Its state columns by model, then its neighbours; no fleet (no battery, no failures): no status, no energy.
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->inspector_text().startsWith(QString("drone %1\ndrone:\n  position [").arg(id)), 5000);
    QVERIFY(window_->sandbox()->inspector_text().contains("\n  velocity ["));
    QVERIFY(window_->sandbox()->inspector_text().contains("neighbours ("));
    QVERIFY(!window_->sandbox()->inspector_text().contains("energy used"));
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
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    window_->sandbox()->view()->setFocus(Qt::MouseFocusReason);  // the view clicked: its single keys work
    QTest::keyClick(window_->sandbox()->view(), Qt::Key_Space);
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->engine().snapshot()->state == RunState::running, 5000);
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->engine().snapshot()->time > 0.2, 20000);
    QTest::keyClick(window_->sandbox()->view(), Qt::Key_Space);
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->engine().snapshot()->state == RunState::paused, 5000);
    // The live plots got rows and drew them.
    QTRY_VERIFY_WITH_TIMEOUT(window_->sandbox()->charts()->series(0)->count() >= 1, 5000);
  }

  // Single keys act on the view only: a focused slider takes Right, a field takes R and -, a list its
  // keys; R on the view asks before it drops a run that has begun.
  void keys_reach_the_control_with_the_focus() {
    window_->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    SandboxPage& sandbox = *window_->sandbox();
    for (int i = 0; i < 10; ++i) sandbox.step();
    settle();
    QSlider* slider = sandbox.behavior_panel()->slider("cohesion_weight");
    const int at = slider->value();
    slider->setFocus(Qt::MouseFocusReason);
    QTest::keyClick(slider, Qt::Key_Right);
    settle();
    QVERIFY2(slider->value() > at && slider->value() <= at + 2, qPrintable(QString("%1 -> %2").arg(at).arg(slider->value())));
    QCOMPARE(sandbox.engine().snapshot()->step, std::uint64_t(10));  // not stepped
    const double zoom = sandbox.view()->world_to_px().m11();
    NumberField* field = sandbox.drones_box();
    field->setFocus(Qt::MouseFocusReason);
    QTest::keyClicks(field, "r-");
    settle();
    QCOMPARE(sandbox.engine().snapshot()->step, std::uint64_t(10));  // not reset
    QCOMPARE(sandbox.view()->world_to_px().m11(), zoom);             // not zoomed
    // A disabled field takes no focus: the keys go to whatever has it (the behavior box here), not to R.
    sandbox.behavior_box()->setFocus(Qt::MouseFocusReason);
    QTest::mouseClick(window_->findChild<QWidget*>("pacing_amount"), Qt::LeftButton);
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_R);
    settle();
    QCOMPARE(sandbox.engine().snapshot()->step, std::uint64_t(10));
    // R on the view: asked first; Cancel keeps the run.
    sandbox.view()->setFocus(Qt::MouseFocusReason);
    int asked = 0;
    QTimer::singleShot(200, [&asked] {
      for (QWidget* w : QApplication::topLevelWidgets())
        if (auto* box = qobject_cast<QMessageBox*>(w); box && box->isVisible()) ++asked, box->button(QMessageBox::Cancel)->click();
    });
    QTest::keyClick(sandbox.view(), Qt::Key_R);
    settle();
    QCOMPARE(asked, 1);
    QCOMPARE(sandbox.engine().snapshot()->step, std::uint64_t(10));
    window_->activateWindow();  // back from the dialog, as a person's click on the view
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    sandbox.view()->setFocus(Qt::MouseFocusReason);
    QTimer::singleShot(200, [&asked] {
      for (QWidget* w : QApplication::topLevelWidgets())
        if (auto* box = qobject_cast<QMessageBox*>(w); box && box->isVisible()) ++asked, box->button(QMessageBox::Reset)->click();
    });
    QTest::keyClick(sandbox.view(), Qt::Key_R);
    settle();
    QCOMPARE(asked, 2);
    QCOMPARE(sandbox.engine().snapshot()->step, std::uint64_t(0));
  }

  // The window fits a 1366 x 768 laptop screen in every mode, and tabbing through the sandbox's panel
  // never scrolls it sideways.
  void the_window_fits_a_laptop_screen() {
    for (auto m : {MainWindow::Mode::sandbox, MainWindow::Mode::queue, MainWindow::Mode::map_creator, MainWindow::Mode::tune,
                   MainWindow::Mode::replay}) {
      window_->set_mode(m);
      QApplication::processEvents();
      const QSize min = window_->minimumSizeHint().expandedTo(window_->minimumSize());
      QVERIFY2(min.width() <= 1366 && min.height() <= 720,
               qPrintable(QString("mode %1: the window needs %2 x %3 px").arg(int(m)).arg(min.width()).arg(min.height())));
    }
    window_->set_mode(MainWindow::Mode::sandbox);
    window_->resize(1366, 720);
    QApplication::processEvents();
    auto* scroll = qobject_cast<QScrollArea*>(window_->sandbox()->controls());
    QVERIFY(scroll);
    window_->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    window_->sandbox()->behavior_box()->setFocus(Qt::TabFocusReason);
    for (int i = 0; i < 60; ++i) {
      QTest::keyClick(QApplication::focusWidget(), Qt::Key_Tab);
      QVERIFY2(scroll->horizontalScrollBar()->value() == 0,
               qPrintable(QString("Tab %1 (%2) scrolled the panel sideways").arg(i).arg(QApplication::focusWidget()->objectName())));
    }
  }

  // On a 1366 x 768 laptop screen each live chart is tall enough that Qt Charts draws every label
  // (title, tick numbers, axis title) in full: an elided one ends in "...".
  void the_live_charts_are_readable_on_a_laptop_screen() {
    window_->set_mode(MainWindow::Mode::sandbox);
    window_->resize(1366, 720);
    SandboxPage& sandbox = *window_->sandbox();
    sandbox.start();
    QTRY_VERIFY_WITH_TIMEOUT(sandbox.charts()->series(0)->count() >= 2, 5000);
    sandbox.pause();
    QApplication::processEvents();
    for (int i = 0; i < 4; ++i) {
      QChartView* view = sandbox.charts()->view(i);
      int numbers = 0;
      for (QGraphicsItem* item : view->scene()->items()) {
        auto* text = dynamic_cast<QGraphicsTextItem*>(item);
        if (!text || !text->isVisible()) continue;
        const QString s = text->toPlainText();
        QVERIFY2(!s.endsWith("...") && !s.endsWith(QChar(0x2026)),
                 qPrintable(QString("chart %1 (%2 x %3 px) elides '%4'").arg(i).arg(view->width()).arg(view->height()).arg(s)));
        bool number = false;
        s.toDouble(&number);
        numbers += number;
      }
      QVERIFY2(numbers >= 6, qPrintable(QString("chart %1 shows %2 tick numbers").arg(i).arg(numbers)));
    }
  }

  // Tab from the map box goes on to the map's own parameters (rebuilt rows keep their place).
  void tab_goes_from_the_map_to_its_parameters() {
    window_->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    SandboxPage& sandbox = *window_->sandbox();
    sandbox.map_box()->setCurrentText("empty");
    settle();
    sandbox.map_box()->setCurrentText("forest");
    settle();
    QApplication::processEvents();
    sandbox.map_box()->setFocus(Qt::TabFocusReason);
    QTest::keyClick(sandbox.map_box(), Qt::Key_Tab);
    QWidget* next = QApplication::focusWidget();
    QVERIFY2(next && sandbox.map_panel()->isAncestorOf(next), qPrintable(next ? next->objectName() : QString("nothing")));
  }

  // The sandbox pauses on the very step that reaches the test's time, whatever the pacing, and Save as
  // test keeps that time.
  void the_pause_at_the_tests_end_is_exact() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.path() + "/short.json", R"({"name": "short", "behavior": "flocking", "drones": 4, "seed": 2,
      "map": {"name": "forest", "params": {"size": 300}}, "time": 2})"));
    SandboxPage& sandbox = *window_->sandbox();
    QVERIFY(sandbox.open_test(dir.path() + "/short.json").empty());
    window_->findChild<QComboBox*>("pacing")->setCurrentText("as fast as possible");
    sandbox.start();
    QTRY_VERIFY_WITH_TIMEOUT(sandbox.engine().snapshot()->state == RunState::paused && sandbox.engine().snapshot()->time > 0, 20000);
    settle();
    QCOMPARE(sandbox.engine().snapshot()->step, std::uint64_t(120));
    QTRY_VERIFY_WITH_TIMEOUT(sandbox.time_label()->text() == "t = 2.0 s", 5000);
    QVERIFY2(sandbox.last_message().startsWith("paused at t = 2.0 s, the test's time"), qPrintable(sandbox.last_message()));
    std::string why;
    const auto saved = sandbox.engine().as_test(&why);
    QVERIFY2(saved, why.c_str());
    QCOMPARE(saved->time, 2.0);
  }

  // A named drone configuration: choosing one makes the box read its name (not the test's
  // "large-custom"), and no name is saved twice (a built-in's is refused, a saved one's replaced).
  void drone_configurations_one_name_each() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.path() + "/custom.json", R"({"name": "custom", "behavior": "flocking", "drones": 4, "seed": 2,
      "drone": {"base": "large", "max_speed": 9}, "map": {"name": "forest", "params": {"size": 300}}, "time": 5})"));
    SandboxPage& sandbox = *window_->sandbox();
    QVERIFY(sandbox.open_test(dir.path() + "/custom.json").empty());
    QComboBox* box = sandbox.drone_config_box();
    QCOMPARE(box->currentText(), QString("large-custom"));
    for (const char* name : {"small", "medium"}) {
      box->setCurrentText(name);
      Q_EMIT box->activated(box->currentIndex());  // as a person choosing it
      settle();
      sandbox.poll();
      QCOMPARE(box->currentText(), QString(name));
      const auto& all = builtin_drone_configs();
      const auto it = std::find_if(all.begin(), all.end(), [&](const DroneConfig& c) { return c.name == name; });
      QVERIFY(it != all.end());
      QCOMPARE(sandbox.engine().current_test()->groups[0].drone.max_speed, it->max_speed);
    }
    QVERIFY2(sandbox.save_drone_config_as("small").find("'small' is a built-in configuration") != std::string::npos, qPrintable(sandbox.last_message()));
    QVERIFY(sandbox.save_drone_config_as("mine").empty());
    QVERIFY(sandbox.save_drone_config_as("mine").empty());
    QStringList names;
    for (int i = 0; i < box->count(); ++i) names << box->itemText(i);
    QCOMPARE(names.count("small"), 1);
    QCOMPARE(names.count("mine"), 1);
    QCOMPARE(box->currentText(), QString("mine"));
  }

  // The wind's velocity (-1000 to 1000 m/s) by slider: fine near 0 (a normal wind can be set), monotonic,
  // the ends exact, 0 and 3 m/s on positions of their own.
  void wind_sliders_are_fine_near_zero() {
    ParamPanel* wind = window_->sandbox()->model_panel("wind");
    QSlider* slider = wind->slider("velocity.x");
    QVERIFY(slider);
    QCOMPARE(wind->slider_value("velocity.x", slider->minimum()), -1000.0);
    QCOMPARE(wind->slider_value("velocity.x", slider->maximum()), 1000.0);
    double last = -1e9, largest_near = 0;
    bool zero = false, three = false;
    for (int s = slider->minimum(); s <= slider->maximum(); ++s) {
      const double v = wind->slider_value("velocity.x", s);
      QVERIFY2(v >= last, qPrintable(QString("position %1: %2 after %3").arg(s).arg(v).arg(last)));
      if (std::fabs(v) <= 10 && std::fabs(last) <= 10) largest_near = std::max(largest_near, v - last);
      zero = zero || v == 0;
      three = three || v == 3;
      last = v;
    }
    QVERIFY2(largest_near <= 0.2 + 1e-9, qPrintable(QString("a step of %1 m/s within 10 m/s of calm").arg(largest_near)));
    QVERIFY(zero && three);
    wind->set_value("velocity.x", 3);
    QCOMPARE(wind->slider_value("velocity.x", slider->value()), 3.0);
    // Arrow keys from 3 m/s (a breeze): each press moves on (a live change), never stuck on a position
    // that rounds back to 3.
    window_->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    settle();
    QApplication::processEvents();
    slider = wind->slider("velocity.x");
    QCOMPARE(wind->value("velocity.x"), 3.0);
    slider->setFocus(Qt::MouseFocusReason);
    for (int i = 0; i < 3; ++i) QTest::keyClick(slider, Qt::Key_Right);
    QVERIFY2(wind->value("velocity.x") > 3 && wind->value("velocity.x") <= 3.3, qPrintable(QString::number(wind->value("velocity.x"))));
  }

  // With a radio on, the Communication box says how many messages are in flight, or why there are none
  // (links are messages, and only a behavior that broadcasts sends).
  void the_comm_box_says_why_no_links_are_drawn() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.path() + "/radio.json", R"({"name": "radio", "behavior": "flocking", "drones": 6, "seed": 2,
      "map": {"name": "forest", "params": {"size": 300}}, "time": 5, "comm": {"range": 80}})"));
    SandboxPage& sandbox = *window_->sandbox();
    QVERIFY(sandbox.open_test(dir.path() + "/radio.json").empty());
    for (int i = 0; i < 5; ++i) sandbox.step();
    settle();
    QTRY_VERIFY_WITH_TIMEOUT(sandbox.comm_note()->text().startsWith("No messages in flight"), 5000);
    QVERIFY(sandbox.comm_note()->text().contains("only a behavior that broadcasts sends any (flocking"));
    QVERIFY(write_file(dir.path() + "/radio.json", R"({"name": "radio", "behavior": {"name": "pheromone_avoidance", "params": {"sharing": 1}},
      "drones": 6, "seed": 2, "map": {"name": "forest", "params": {"size": 300}}, "time": 5, "comm": {"range": 80}})"));
    QVERIFY(sandbox.open_test(dir.path() + "/radio.json").empty());
    for (int i = 0; i < 5; ++i) sandbox.step();
    settle();
    QTRY_VERIFY_WITH_TIMEOUT(sandbox.comm_note()->text().contains("messages delivered for the next step"), 5000);
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
