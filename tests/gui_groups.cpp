// Groups, batteries and failures in the desktop, as a person uses them: a two-group test draws each
// group in its colour with a legend naming both (one group keeps today's look); the group box chooses
// whose controls, so group B's drone count changes B alone; a saved test keeps its groups; failure
// rates and "fail a drone" are recorded changes, and the inspector says a drone's group, status and
// energy; the energy properties sit in their own folded section with their units, and so does sensor noise;
// a named drone chosen in its box flies with every property it has.
#include "common.hpp"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLineEdit>
#include <QPushButton>
#include <QRegularExpression>
#include <QSettings>
#include <QSpinBox>
#include <QTemporaryDir>
#include <QToolButton>
#include <algorithm>

#include "main_window.hpp"
#include "number_field.hpp"
#include "param_panel.hpp"
#include "sandbox_page.hpp"
#include "view.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

constexpr const char* two_groups = R"({"name": "two", "groups": [
  {"name": "surveyors", "drones": 6, "drone": "large", "behavior": "pheromone_avoidance", "spawn": {"point": [150, 150]}},
  {"name": "inspectors", "drones": 12, "behavior": "random_walk"}],
  "map": {"name": "forest", "params": {"size": 600}}, "targets": {"count": 400}, "time": 300, "seed": 4})";

constexpr const char* one_group = R"({"name": "one", "behavior": "random_walk", "drones": 12,
  "map": {"name": "forest", "params": {"size": 600}}, "targets": {"count": 400}, "time": 300, "seed": 4})";

/// Whether `c` is within a few levels of `want` in each channel (antialiasing aside, the disc's centre is exact).
bool near(QRgb c, const QColor& want) {
  return std::abs(qRed(c) - want.red()) <= 12 && std::abs(qGreen(c) - want.green()) <= 12 && std::abs(qBlue(c) - want.blue()) <= 12;
}

/// How many of group `g`'s flying drones show their group's colour at their centre pixel.
int drones_in_colour(const QImage& image, const Snapshot& snap, const QTransform& t, std::uint32_t g, const QColor& colour) {
  int n = 0;
  for (std::uint32_t i = 0; i < snap.positions.size(); ++i) {
    if (snap.group_of(i) != g || snap.status_of(i) != DroneStatus::flying) continue;
    const QPoint p = t.map(QPointF(snap.positions[i].x, snap.positions[i].y)).toPoint();
    n += near(image.pixel(p), colour);
  }
  return n;
}

}  // namespace

class GuiGroups : public QObject {
  Q_OBJECT
  std::unique_ptr<PluginHost> host_ = builtin_host();
  std::unique_ptr<MainWindow> window_;

  SandboxPage& sandbox() { return *window_->sandbox(); }
  void settle() {
    QApplication::processEvents();
    sandbox().poll();
    sandbox().engine().sync();
    sandbox().poll();
  }
  void steps(int n) {
    for (int i = 0; i < n; ++i) sandbox().step();
    settle();
  }
  std::vector<Change> live_changes() { return sandbox().engine().timeline(); }
  static bool has_change(const std::vector<Change>& timeline, const std::string& key, double value) {
    return std::any_of(timeline.begin(), timeline.end(), [&](const Change& c) { return c.key == key && c.value == value; });
  }

 private Q_SLOTS:
  void init() {
    QSettings().clear();
    window_ = std::make_unique<MainWindow>(*host_);
    window_->resize(1400, 900);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    QVERIFY(sandbox().open_test_spec(parse_test(two_groups, "two", *host_)).empty());
  }
  void cleanup() { window_.reset(); }

  void each_group_in_its_colour_with_a_legend() {
    steps(30);
    const auto snap = sandbox().engine().snapshot();
    QCOMPARE(snap->groups.size(), std::size_t(2));
    ViewOptions options;
    options.trails = false;
    const QSize size(900, 900);
    const QTransform t = fit_transform(snap->scene->map.bounds, QSizeF(size));
    const QImage image = render_frame(*snap, options, size, t);
    // Orange and blue, the plots' first two group colours; every drone (overlaps aside) in its own.
    QCOMPARE(group_colour(0, 2), QColor(0xE6, 0x9F, 0x00));
    QCOMPARE(group_colour(1, 2), QColor(0x00, 0x72, 0xB2));
    QVERIFY2(drones_in_colour(image, *snap, t, 0, group_colour(0, 2)) >= 5, "surveyors not orange");
    QVERIFY2(drones_in_colour(image, *snap, t, 1, group_colour(1, 2)) >= 10, "inspectors not blue");
    QCOMPARE(drones_in_colour(image, *snap, t, 1, group_colour(0, 2)), 0);
    // The legend names both groups, and is drawn (top left).
    const QStringList legend = legend_rows(*snap);
    QCOMPARE(legend, QStringList({"surveyors: 6 flying", "inspectors: 12 flying"}));
    int orange_in_legend = 0;
    for (int y = 8; y < 60; ++y)
      for (int x = 8; x < 40; ++x) orange_in_legend += near(image.pixel(x, y), group_colour(0, 2));
    QVERIFY(orange_in_legend > 20);
    // One group keeps today's look: blue drones, no legend.
    QVERIFY(sandbox().open_test_spec(parse_test(one_group, "one", *host_)).empty());
    steps(5);
    const auto single = sandbox().engine().snapshot();
    QVERIFY(legend_rows(*single).isEmpty());
    const QImage plain = render_frame(*single, options, size, t);
    QVERIFY(drones_in_colour(plain, *single, t, 0, group_colour(0, 1)) >= 10);
    QCOMPARE(group_colour(0, 1), QColor(0x1f, 0x3f, 0x8c));
    QVERIFY(!sandbox().group_box()->isVisibleTo(window_.get()));
  }

  void the_group_box_edits_the_chosen_group_alone() {
    QVERIFY(sandbox().group_box()->isVisibleTo(window_.get()));
    QCOMPARE(sandbox().group_box()->count(), 2);
    QCOMPARE(sandbox().behavior_box()->currentText(), QString("pheromone_avoidance"));
    QCOMPARE(sandbox().drones_box()->value(), 6.0);
    QCOMPARE(sandbox().drone_panel()->value("radius"), 2.5);  // "large"
    steps(10);
    sandbox().group_box()->setCurrentText("inspectors");
    settle();
    QCOMPARE(sandbox().behavior_box()->currentText(), QString("random_walk"));
    QCOMPARE(sandbox().drones_box()->value(), 12.0);
    QCOMPARE(sandbox().drone_panel()->value("radius"), 1.0);  // "small"
    sandbox().drones_box()->setValue(20);  // as a person typing it
    sandbox().behavior_panel()->spin_box("max_duration")->setValue(20);
    sandbox().drone_panel()->spin_box("max_speed")->setValue(7);
    settle();
    const TestSpec now = *sandbox().engine().current_test();
    QCOMPARE(now.groups[1].drones, std::size_t(20));
    QCOMPARE(now.groups[1].behavior.params.get("max_duration"), 20.0);
    QCOMPARE(now.groups[1].drone.max_speed, 7.0);
    QCOMPARE(now.groups[0].drones, std::size_t(6));  // B's edits leave A as it was
    QCOMPARE(now.groups[0].drone.max_speed, 20.0);
    const auto timeline = live_changes();
    QVERIFY(has_change(timeline, "groups.inspectors.drones", 20));
    QVERIFY(has_change(timeline, "groups.inspectors.behavior.params.max_duration", 20));
    QVERIFY(has_change(timeline, "groups.inspectors.drone.max_speed", 7));
    // The drones: 8 new ones in B (ids after all others), A's 6 untouched.
    const auto snap = sandbox().engine().snapshot();
    QCOMPARE(snap->positions.size(), std::size_t(26));
    QCOMPARE(std::count(snap->drone_groups.begin(), snap->drone_groups.end(), 1u), 20);
    // Back to A: its values, and a start-state edit (the seed) keeps B's live values.
    sandbox().group_box()->setCurrentText("surveyors");
    settle();
    QCOMPARE(sandbox().drones_box()->value(), 6.0);
    sandbox().seed_box()->setText("9");
    Q_EMIT sandbox().seed_box()->editingFinished();  // as Enter does
    settle();
    const TestSpec reloaded = *sandbox().engine().current_test();
    QCOMPARE(reloaded.seed, std::uint64_t(9));
    QCOMPARE(reloaded.groups.size(), std::size_t(2));
    QCOMPARE(reloaded.groups[1].drones, std::size_t(20));
    QCOMPARE(reloaded.groups[0].behavior.name, std::string("pheromone_avoidance"));
    QCOMPARE(sandbox().group_box()->currentText(), QString("surveyors"));
  }

  void a_saved_test_keeps_its_groups() {
    steps(20);
    sandbox().group_box()->setCurrentText("inspectors");
    settle();
    sandbox().drones_box()->setValue(4);
    steps(10);
    QTemporaryDir dir;
    const QString file = dir.path() + "/saved.json";
    QCOMPARE(sandbox().save_test(file), std::string());
    const auto saved = load_tests(file.toStdString(), *host_);
    QCOMPARE(saved.size(), std::size_t(1));
    const TestSpec& t = saved[0];
    QVERIFY(t.named_groups);
    QCOMPARE(t.groups.size(), std::size_t(2));
    QCOMPARE(t.groups[0].name, std::string("surveyors"));
    QCOMPARE(t.groups[0].drone.radius, 2.5);
    QCOMPARE(t.groups[0].spawn, std::optional<Vec2>(Vec2{150, 150}));
    QCOMPARE(t.groups[1].name, std::string("inspectors"));
    QCOMPARE(t.groups[1].drones, std::size_t(12));  // the start state; the change is timed
    QCOMPARE(t.changes.size(), std::size_t(1));
    QCOMPARE(t.changes[0].key, std::string("groups.inspectors.drones"));
    QCOMPARE(t.changes[0].value, 4.0);
    // What the sandbox would save again is what was read: the groups round-trip whole.
    QCOMPARE(t.groups, sandbox().engine().as_test()->groups);
    // And it opens again with its two groups.
    QVERIFY(sandbox().open_test(file).empty());
    QCOMPARE(sandbox().group_box()->count(), 2);
  }

  void failures_set_in_the_desktop_are_recorded() {
    steps(10);
    sandbox().model_panel("failures")->spin_box("drone_mtbf")->setValue(600);  // as typed
    settle();
    QCOMPARE(sandbox().engine().current_test()->failures.drone_mtbf, 600.0);
    QVERIFY(has_change(live_changes(), "failures.drone_mtbf", 600));
    // Fail the inspected drone: click it, then the button that names it.
    QVERIFY(!sandbox().fail_button()->isEnabled());
    sandbox().engine().select(7);
    settle();
    QTRY_VERIFY(sandbox().fail_button()->isEnabled());
    QCOMPARE(sandbox().fail_button()->text(), QString("Fail drone 7"));
    QTest::mouseClick(sandbox().fail_button(), Qt::LeftButton);
    settle();
    QVERIFY(has_change(live_changes(), "fail.drone", 7));
    steps(1);
    auto snap = sandbox().engine().snapshot();
    QCOMPARE(snap->status_of(7), DroneStatus::failed);
    QVERIFY(snap->selected && snap->selected->fleet);
    // Its status, and the fleet's columns (no battery model: none left to count).
    QTRY_VERIFY(sandbox().inspector_text().startsWith("drone 7 of group inspectors: failed\n"));
    QVERIFY(sandbox().inspector_text().contains("\nfleet:\n"));
    QVERIFY(sandbox().inspector_text().contains("\n  battery left inf Wh\n"));
    QTRY_VERIFY(!sandbox().fail_button()->isEnabled());  // it is down already
    QVERIFY(legend_rows(*snap).contains("inspectors: 11 flying, 1 stopped"));
    // The saved test replays both: the rate and the event at their times.
    QTemporaryDir dir;
    QCOMPARE(sandbox().save_test(dir.path() + "/failed.json"), std::string());
    const auto saved = load_tests((dir.path() + "/failed.json").toStdString(), *host_);
    QVERIFY(has_change(saved[0].changes, "failures.drone_mtbf", 600));
    QVERIFY(has_change(saved[0].changes, "fail.drone", 7));
    // salsa run of it ends where the sandbox is: each drone's group and status in fleet.csv as shown.
    const CliResult r = run_salsa({"run", "failed.json", "--out", "out", "--no-plots", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QStringList fleet = non_empty_lines(read_file(dir.path() + "/out/failed/fleet.csv"));
    QCOMPARE(fleet.value(0), QString("id,group,status,since,energy_used_Wh,battery_left"));
    QCOMPARE(fleet.size(), 1 + 18);
    for (std::uint32_t id = 0; id < 18; ++id) {
      const QStringList cells = fleet[static_cast<int>(id) + 1].split(',');
      QCOMPARE(cells[0].toUInt(), id);
      QCOMPARE(cells[1], q(snap->groups[snap->group_of(id)].name));
      QCOMPARE(cells[2], QString(snap->status_of(id) == DroneStatus::failed ? "failed" : "flying"));
    }
  }

  void battery_properties_fold_away_with_their_units() {
    // One group: the plain keys, as saved tests had them.
    QVERIFY(sandbox().open_test_spec(parse_test(one_group, "one", *host_)).empty());
    ParamPanel* battery = sandbox().battery_panel();
    QVERIFY(!battery->isVisibleTo(window_.get()));  // folded while no battery is in use
    QVERIFY(!sandbox().drone_panel()->spin_box("battery_capacity"));
    for (const char* name : {"battery_capacity", "blade_power", "induced_power", "tip_speed", "induced_velocity", "parasite_drag",
                             "charge_power", "charge_radius", "return_to_base", "return_reserve", "resume_charge"})
      QVERIFY2(battery->spin_box(name), name);  // return to base's with the battery's
    auto* capacity = battery->spin_box("battery_capacity");
    QCOMPARE(capacity->spec().unit, std::string("Wh"));
    QCOMPARE(capacity->text(), QString("none"));  // 0: no battery model
    QTest::mouseClick(sandbox().battery_toggle(), Qt::LeftButton);
    QVERIFY(battery->isVisibleTo(window_.get()));
    capacity->setValue(50);
    settle();
    QVERIFY(has_change(live_changes(), "drone.battery_capacity", 50));
    QCOMPARE(sandbox().engine().current_test()->groups[0].drone.battery_capacity, 50.0);
    steps(60);
    sandbox().engine().select(0);
    settle();
    QTRY_VERIFY(sandbox().inspector_text().contains("battery left"));
    const auto snap = sandbox().engine().snapshot();
    const StateLine* left = snap->selected ? snap->selected->line("battery_left") : nullptr;
    const StateLine* used = snap->selected ? snap->selected->line("energy_used") : nullptr;
    QVERIFY(left && used && left->unit == "J");
    QVERIFY(left->values[0] < 50 * 3600);  // drawn from its 50 Wh
    QVERIFY(used->values[0] > 0);
    QVERIFY(sandbox().inspector_text().startsWith("drone 0: flying\n"));
    QVERIFY(sandbox().inspector_text().contains(QRegularExpression("\n  energy used [0-9.]+ Wh\n")));
  }

  // Sensor noise is a section of its own, folded like the battery's: its five properties there and
  // nowhere else; a change is recorded; a test with noise opens with the section shown.
  void noise_properties_fold_away() {
    QVERIFY(sandbox().open_test_spec(parse_test(one_group, "one", *host_)).empty());
    ParamPanel* noise = sandbox().noise_panel();
    QVERIFY(!noise->isVisibleTo(window_.get()));
    for (const char* name : {"position_noise", "neighbour_noise", "obstacle_noise", "miss_probability", "false_detection_rate"}) {
      QVERIFY2(noise->spin_box(name), name);
      QVERIFY2(!sandbox().drone_panel()->spin_box(name) && !sandbox().battery_panel()->spin_box(name), name);
    }
    std::string noisy = one_group;  // a test with noise opens with the section shown
    noisy.insert(noisy.find("\"drones\""), R"("drone": {"position_noise": 2}, )");
    QVERIFY(sandbox().open_test_spec(parse_test(noisy, "noisy", *host_)).empty());
    QVERIFY(noise->isVisibleTo(window_.get()));
    QCOMPARE(noise->value("position_noise"), 2.0);
    noise->spin_box("miss_probability")->setValue(0.2);
    settle();
    QVERIFY(has_change(live_changes(), "drone.miss_probability", 0.2));
    QCOMPARE(sandbox().engine().current_test()->groups[0].drone.miss_probability, 0.2);
    QTest::mouseClick(sandbox().noise_toggle(), Qt::LeftButton);  // folds away again
    QVERIFY(!noise->isVisibleTo(window_.get()));
  }

  // Choosing a named drone applies every property of it to the running drones, not the panel alone:
  // "large" has 12 obstacle rays where "small" has 8, and a saved test replays them.
  void a_chosen_drone_flies_with_all_its_properties() {
    QVERIFY(sandbox().open_test_spec(parse_test(one_group, "one", *host_)).empty());
    steps(5);
    QComboBox* config = sandbox().drone_config_box();
    QCOMPARE(config->currentText(), QString("small"));
    config->setFocus();
    QTest::keyClick(config, Qt::Key_End);  // the last built-in: large (as a person picks it)
    QCOMPARE(config->currentText(), QString("large"));
    settle();
    const DroneConfig& large = builtin_drone_configs().back();
    QCOMPARE(large.obstacle_rays, 12);
    QCOMPARE(sandbox().drone_panel()->value("obstacle_rays"), 12.0);
    sandbox().start();
    QTRY_VERIFY(sandbox().engine().snapshot()->step >= 20);
    sandbox().pause();
    settle();
    // What flies is the whole configuration, each property as "large" has it.
    const DroneConfig flying = sandbox().engine().snapshot()->groups.at(0).drone;
    QCOMPARE(flying.obstacle_rays, 12);
    for (const DroneProperty& p : drone_schema()) QVERIFY2(p.get(flying) == p.get(large), p.spec.name.c_str());
    QVERIFY(has_change(live_changes(), "drone.obstacle_rays", 12));
    // Saved, the test holds the rays as a timed change, and flies with them when opened again.
    QTemporaryDir dir;
    const QString file = dir.path() + "/large.json";
    QCOMPARE(sandbox().save_test(file), std::string());
    QVERIFY(read_file(file).contains("\"drone.obstacle_rays\": 12"));
    QVERIFY(sandbox().open_test(file).empty());
    steps(10);
    QCOMPARE(sandbox().engine().snapshot()->groups.at(0).drone.obstacle_rays, 12);
  }
};

QTEST_MAIN(GuiGroups)
#include "gui_groups.moc"
