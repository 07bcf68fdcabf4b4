// Communication, wind and sensor noise in the desktop, as a person uses them: ticking "comm" starts the
// test over with it; a value typed into a model's panel is a recorded live change (the wind starts so);
// View → Communication links draws who hears whom, the wind is drawn as arrows; the inspector lists
// what a drone hears, its air velocity and where it believes it is; a saved test replays it all with
// salsa run. A model added with add_test_model gets a panel of its own, with no line of the desktop's.
#include "common.hpp"

#include <QAbstractSpinBox>
#include <QComboBox>
#include <QGroupBox>
#include <QToolButton>
#include <QSettings>
#include <QTemporaryDir>
#include <algorithm>

#include "main_window.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "number_field.hpp"
#include "param_panel.hpp"
#include "sandbox_page.hpp"
#include "view.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

constexpr const char* flock = R"({"name": "radio", "behavior": {"name": "pheromone_avoidance", "params": {"sharing": 1}}, "drones": 20,
  "map": {"name": "empty", "params": {"size": 400}}, "targets": {"count": 100}, "time": 300, "seed": 3})";

/// Pixels of `image` that are the links' purple (drawn at alpha 90 over the light background).
int purple(const QImage& image) {
  int n = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QRgb c = image.pixel(x, y);
      n += qBlue(c) > qGreen(c) + 25 && qRed(c) > qGreen(c) + 10;
    }
  return n;
}

bool has_change(const std::vector<Change>& timeline, const std::string& key, double value) {
  return std::any_of(timeline.begin(), timeline.end(), [&](const Change& c) { return c.key == key && c.value == value; });
}

int sway_applied = 0;  // the running simulation was told of a change of "sway"

/// "sway": {"amplitude": m, "drift": [x, y] in m/s, "pulse": true}: a model of this test alone, its
/// numbers in TestSpec::extra_numbers.
TestModel sway() {
  auto number = [](const char* name, double min, double max, const char* unit) -> ModelField {
    return {{name, 0, min, max, unit, "test-only"}, false,
            [name](const TestSpec& t) {
              const auto it = t.extra_numbers.find(std::string("sway.") + name);
              return it == t.extra_numbers.end() ? 0.0 : it->second;
            },
            [name](TestSpec& t, double v) { t.extra_numbers[std::string("sway.") + name] = v; }};
  };
  ModelField pulse = number("pulse", 0, 1, "");
  pulse.spec.step = 1;
  pulse.flag = true;
  return {.key = "sway",
          .meaning = "sway: a model declared by a test (\"sway\": {...}). Its numbers are\nset as sway.<name>.",
          .fields = {number("amplitude", 0, 10, "m"), number("drift.x", -10, 10, "m/s"), number("drift.y", -10, 10, "m/s"), pulse},
          .in_use = [](const TestSpec& t) { return !t.extra_numbers.empty(); },
          .apply = [](Simulation&, const TestSpec&) { ++sway_applied; },
          // Its own per-drone state: each flying drone's offset drifts at "drift" (m/s).
          .simulate = [](const TestSpec& t) {
            const auto it = t.extra_numbers.find("sway.drift.x");
            const double drift = it == t.extra_numbers.end() ? 0.0 : it->second;
            return DroneModel{"sway", {{"sway_offset", "m", "how far the sway carried it", ""}}, ModelPhase::moved,
                              [drift](const Simulation& sim, ModelState& state) {
                                for (double& x : state.f64("sway_offset")) x += drift * sim.dt();
                              }};
          }};
}

}  // namespace

class GuiEnvironment : public QObject {
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
  void type(QAbstractSpinBox* box, const QString& text) {
    box->setFocus();
    box->selectAll();
    QTest::keyClicks(box, text);
    QTest::keyClick(box, Qt::Key_Return);
    settle();
  }

 private Q_SLOTS:
  void initTestCase() { add_test_model(sway()); }  // before any window is made
  void init() {
    QSettings().clear();
    window_ = std::make_unique<MainWindow>(*host_);
    window_->resize(1400, 900);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    QVERIFY(sandbox().open_test_spec(parse_test(flock, "radio", *host_)).empty());
  }
  void cleanup() { window_.reset(); }

  void a_radio_ticked_typed_drawn_and_saved() {
    QGroupBox* comm = sandbox().model_box("comm");
    QVERIFY(!comm->isChecked());  // the test has no "comm"
    QVERIFY(!sandbox().engine().current_test()->comm.on);
    comm->setChecked(true);  // as a click on its title does: a new start state
    settle();
    QTRY_VERIFY(sandbox().engine().current_test() && sandbox().engine().current_test()->comm.on);
    QCOMPARE(sandbox().engine().current_test()->comm.range, 134.0);
    // Typed: a shorter range, live and recorded.
    auto* range = sandbox().model_panel("comm")->spin_box("range");
    QVERIFY(range);
    type(range, "60");
    QCOMPARE(sandbox().engine().current_test()->comm.range, 60.0);
    const auto timeline = sandbox().engine().timeline();
    QVERIFY(std::any_of(timeline.begin(), timeline.end(), [](const Change& c) { return c.key == "comm.range" && c.value == 60; }));
    steps(30);
    // Links: deliveries within the range only (positions moved at most one step since they were sent).
    const auto snap = sandbox().engine().snapshot();
    QVERIFY(!snap->links.empty());
    for (const auto& [receiver, sender] : snap->links)
      QVERIFY(distance(snap->positions[receiver], snap->positions[sender]) <= 60 + 2 * 10 * snap->dt);
    // View → Communication links draws them; off, no purple.
    ViewOptions options;
    options.trails = false;
    const QSize size(800, 800);
    const QTransform t = fit_transform(snap->scene->map.bounds, QSizeF(size));
    const int without = purple(render_frame(*snap, options, size, t));
    options.links = true;
    const int with = purple(render_frame(*snap, options, size, t));
    QVERIFY2(with > without + 50, qPrintable(QString("purple pixels %1 with links, %2 without").arg(with).arg(without)));
    // The inspector says what a drone hears.
    sandbox().engine().select(snap->links.front().first);
    steps(1);
    QTRY_VERIFY(sandbox().inspector_text().contains("messages next step: "));
    // Saved, the test has the radio and the typed change; salsa run counts its messages.
    QTemporaryDir dir;
    QCOMPARE(sandbox().save_test(dir.path() + "/radio.json"), std::string());
    const auto saved = load_tests((dir.path() + "/radio.json").toStdString(), *host_);
    QVERIFY(saved[0].comm.on);
    QCOMPARE(saved[0].comm.range, 134.0);  // the start state; the change is timed
    QVERIFY(std::any_of(saved[0].changes.begin(), saved[0].changes.end(), [](const Change& c) { return c.key == "comm.range"; }));
    const CliResult r = run_salsa({"run", "radio.json", "--out", "out", "--no-plots", "-q", "--time", "2"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(read_file(dir.path() + "/out/radio/summary.csv").startsWith("time,"));
    QVERIFY(non_empty_lines(read_file(dir.path() + "/out/radio/summary.csv")).value(0).contains("messages_delivered"));
  }

  // Light physics chosen from the set-up's combo box as a person does (keys): a new start state that
  // flies, saves and runs as "physics": "light"; back to box2d, the file says nothing of physics.
  void light_physics_chosen_flown_and_saved() {
    QComboBox* physics = sandbox().physics_box();
    QCOMPARE(physics->currentText(), QString("box2d"));
    physics->setFocus();
    QTest::keyClick(physics, Qt::Key_Down);  // the next item: light
    settle();
    QTRY_VERIFY(sandbox().engine().current_test() && sandbox().engine().current_test()->physics == PhysicsMode::light);
    const Vec2 start = sandbox().engine().snapshot()->positions.front();
    steps(30);
    QVERIFY(sandbox().engine().snapshot()->positions.front() != start);  // it flies
    QTemporaryDir dir;
    QCOMPARE(sandbox().save_test(dir.path() + "/light.json"), std::string());
    QVERIFY(read_file(dir.path() + "/light.json").contains("\"physics\": \"light\""));
    const CliResult r = run_salsa({"run", "light.json", "--out", "out", "--no-plots", "-q", "--time", "2"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(read_file(dir.path() + "/out/light/config.json").contains("\"physics\": \"light\""));
    QTest::keyClick(physics, Qt::Key_Up);
    settle();
    QTRY_VERIFY(sandbox().engine().current_test()->physics == PhysicsMode::box2d);
    QCOMPARE(sandbox().save_test(dir.path() + "/box2d.json"), std::string());
    QVERIFY(!read_file(dir.path() + "/box2d.json").contains("physics"));
  }

  void wind_typed_drawn_and_noise_inspected() {
    // The wind's numbers are live whether or not the test has wind: a typed velocity starts it, recorded.
    QVERIFY(!sandbox().model_box("wind")->isCheckable());
    QVERIFY(!sandbox().engine().current_test()->has_wind());
    sandbox().engine().select(0);  // no wind: the inspector has no wind lines
    steps(1);
    QTRY_VERIFY(sandbox().inspector_text().startsWith("drone 0\n"));
    QVERIFY(!sandbox().inspector_text().contains("air velocity"));
    QVERIFY(!sandbox().inspector_text().contains("wind:"));
    auto* x = sandbox().model_panel("wind")->spin_box("velocity.x");
    QVERIFY(x);
    type(x, "4");
    QVERIFY(sandbox().engine().current_test()->has_wind());
    QCOMPARE(sandbox().engine().current_test()->wind.velocity, (Vec2{4, 0}));
    const auto timeline = sandbox().engine().timeline();
    QVERIFY(std::any_of(timeline.begin(), timeline.end(), [](const Change& c) { return c.key == "wind.velocity.x" && c.value == 4; }));
    // Sensor noise, in the drone panel's own section: typed too.
    QTest::mouseClick(sandbox().noise_toggle(), Qt::LeftButton);
    auto* noise = sandbox().noise_panel()->spin_box("position_noise");
    QVERIFY(noise);
    type(noise, "3");
    QCOMPARE(sandbox().engine().current_test()->groups[0].drone.position_noise, 3.0);
    steps(20);
    // Arrows: every grid sample carries the constant wind (no gusts, no field); drawn, and not when off.
    const auto snap = sandbox().engine().snapshot();
    QCOMPARE(snap->wind.size(), std::size_t(Snapshot::wind_grid * Snapshot::wind_grid));
    for (const auto& [p, w] : snap->wind) QCOMPARE(w, (Vec2{4, 0}));
    ViewOptions options;
    options.trails = false;
    options.targets = false;
    const QSize size(800, 800);
    const QTransform t = fit_transform(snap->scene->map.bounds, QSizeF(size));
    const QImage with = render_frame(*snap, options, size, t);
    options.wind = false;
    const QImage without = render_frame(*snap, options, size, t);
    int changed = 0;
    for (int y = 0; y < size.height(); ++y)
      for (int px = 0; px < size.width(); ++px) changed += with.pixel(px, y) != without.pixel(px, y);
    QVERIFY2(changed > 144 * 20, qPrintable(QString("%1 pixels differ").arg(changed)));
    // The inspector: the wind's columns (air velocity beside the ground's), and the perceived position
    // apart from the true one.
    sandbox().engine().select(0);
    steps(1);
    QTRY_VERIFY(sandbox().inspector_text().contains("\nwind:\n  air velocity ["));
    QVERIFY(sandbox().inspector_text().contains("perceived position ["));
    const auto inspected = sandbox().engine().snapshot()->selected;
    QVERIFY(inspected && inspected->perceived && inspected->line("air_velocity"));
    QVERIFY(distance(*inspected->perceived, inspected->position) > 0);
    const StateLine* ground = inspected->line("velocity");
    const StateLine* air = inspected->line("air_velocity");
    QVERIFY(ground && air && air->unit == "m/s");
    QVERIFY(distance(Vec2{ground->values[0], ground->values[1]} - Vec2{air->values[0], air->values[1]}, Vec2{4, 0}) < 0.01);
    // Saved and run by salsa run: the wind and the noise are in config.json.
    QTemporaryDir dir;
    QCOMPARE(sandbox().save_test(dir.path() + "/windy.json"), std::string());
    const CliResult r = run_salsa({"run", "windy.json", "--out", "out", "--no-plots", "-q", "--time", "2"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QStringList folders = QDir(dir.path() + "/out").entryList(QDir::Dirs | QDir::NoDotAndDotDot);
    QCOMPARE(folders.size(), 1);
    const QByteArray config = read_file(dir.path() + "/out/" + folders[0] + "/config.json");
    QVERIFY(config.contains("\"wind.velocity.x\""));     // live changes: in "changes"
    QVERIFY(config.contains("\"drone.position_noise\""));
  }

  // A model the desktop never heard of, added before the window is made: a box of its own titled from
  // its meaning, a row per field; typed, a live change that the running test takes and Save as test
  // keeps; opened with a test, its values shown and kept in the section through a new start state; a
  // test without it saves without it.
  void a_model_added_by_a_test_gets_its_own_panel() {
    QGroupBox* box = sandbox().model_box("sway");
    QVERIFY(box);
    QCOMPARE(box->title(), QString("sway: a model declared by a test"));
    QVERIFY(!box->isCheckable());
    ParamPanel* panel = sandbox().model_panel("sway");
    QVERIFY(panel->spin_box("amplitude") && panel->spin_box("drift.x") && panel->spin_box("drift.y") && panel->spin_box("pulse"));
    QCOMPARE(panel->spin_box("amplitude")->spec().unit, std::string("m"));
    QTemporaryDir dir;
    QCOMPARE(sandbox().save_test(dir.path() + "/plain.json"), std::string());
    QVERIFY(!read_file(dir.path() + "/plain.json").contains("sway"));
    // Typed: live and recorded.
    sway_applied = 0;
    type(panel->spin_box("amplitude"), "2.5");
    QCOMPARE(sandbox().engine().current_test()->extra_numbers.at("sway.amplitude"), 2.5);
    QVERIFY(sway_applied > 0);
    QVERIFY(has_change(sandbox().engine().timeline(), "sway.amplitude", 2.5));
    QCOMPARE(sandbox().save_test(dir.path() + "/typed.json"), std::string());
    QVERIFY(has_change(load_tests((dir.path() + "/typed.json").toStdString(), *host_)[0].changes, "sway.amplitude", 2.5));
    // Opened with a test that has it: shown; a new start state (another target count) keeps the section.
    std::string with = flock;
    with.insert(with.rfind('}'), R"(, "sway": {"amplitude": 1, "drift": [2, -3], "pulse": true})");
    QVERIFY(sandbox().open_test_spec(parse_test(with, "swaying", *host_)).empty());
    panel = sandbox().model_panel("sway");
    QCOMPARE(panel->value("drift.y"), -3.0);
    QCOMPARE(panel->value("pulse"), 1.0);
    // The inspector shows its state under its name, as the core's models.
    sandbox().engine().select(0);
    steps(60);
    QTRY_VERIFY2(sandbox().inspector_text().contains("\nsway:\n  sway offset 2 m"), qPrintable(sandbox().inspector_text()));
    sandbox().targets_box()->setValue(50);
    settle();
    QTRY_COMPARE(sandbox().engine().current_test()->targets, std::size_t(50));
    const std::map<std::string, double> numbers{{"sway.amplitude", 1}, {"sway.drift.x", 2}, {"sway.drift.y", -3}, {"sway.pulse", 1}};
    QCOMPARE(sandbox().engine().current_test()->extra_numbers, numbers);
    QCOMPARE(sandbox().save_test(dir.path() + "/swaying.json"), std::string());
    QVERIFY(read_file(dir.path() + "/swaying.json").contains("\"sway\": {"));
    QCOMPARE(load_tests((dir.path() + "/swaying.json").toStdString(), *host_)[0].extra_numbers, numbers);
  }
};

QTEST_MAIN(GuiEnvironment)
#include "gui_environment.moc"
