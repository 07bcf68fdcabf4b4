// Communication, wind and sensor noise in the desktop, as a person uses them: ticking
// "Communication" or "Wind" starts the test over with it; a value typed into its panel is a recorded
// live change; View → Communication links draws who hears whom, the wind is drawn as arrows; the
// inspector lists what a drone hears, its air velocity and where it believes it is; a saved test
// replays it all with salsa run.
#include "common.hpp"

#include <QAbstractSpinBox>
#include <QComboBox>
#include <QGroupBox>
#include <QToolButton>
#include <QSettings>
#include <QTemporaryDir>
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
    QGroupBox* comm = sandbox().comm_box();
    QVERIFY(!comm->isChecked());  // the test has no "comm"
    QVERIFY(!sandbox().engine().current_test()->comm.on);
    comm->setChecked(true);  // as a click on its title does: a new start state
    settle();
    QTRY_VERIFY(sandbox().engine().current_test() && sandbox().engine().current_test()->comm.on);
    QCOMPARE(sandbox().engine().current_test()->comm.range, 134.0);
    // Typed: a shorter range, live and recorded.
    auto* range = sandbox().comm_panel()->spin_box("range");
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

  void wind_ticked_typed_drawn_and_noise_inspected() {
    QGroupBox* wind = sandbox().wind_box();
    QVERIFY(!wind->isChecked());
    wind->setChecked(true);
    settle();
    QTRY_VERIFY(sandbox().engine().current_test() && sandbox().engine().current_test()->has_wind());
    QCOMPARE(sandbox().engine().current_test()->wind.velocity, (Vec2{3, 0}));  // ticked over no wind: a breeze to edit
    auto* x = sandbox().wind_panel()->spin_box("velocity.x");
    QVERIFY(x);
    type(x, "4");
    QCOMPARE(sandbox().engine().current_test()->wind.velocity.x, 4.0);
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
    // The inspector: air velocity beside the ground's, and the perceived position apart from the true one.
    sandbox().engine().select(0);
    steps(1);
    QTRY_VERIFY(sandbox().inspector_text().contains("air velocity ("));
    QVERIFY(sandbox().inspector_text().contains("perceived position ("));
    const auto inspected = sandbox().engine().snapshot()->selected;
    QVERIFY(inspected && inspected->perceived && inspected->air_velocity);
    QVERIFY(distance(*inspected->perceived, inspected->position) > 0);
    QVERIFY(distance(inspected->velocity - *inspected->air_velocity, Vec2{4, 0}) < 0.01);
    // Saved and run by salsa run: the wind and the noise are in config.json.
    QTemporaryDir dir;
    QCOMPARE(sandbox().save_test(dir.path() + "/windy.json"), std::string());
    const CliResult r = run_salsa({"run", "windy.json", "--out", "out", "--no-plots", "-q", "--time", "2"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QStringList folders = QDir(dir.path() + "/out").entryList(QDir::Dirs | QDir::NoDotAndDotDot);
    QCOMPARE(folders.size(), 1);
    const QByteArray config = read_file(dir.path() + "/out/" + folders[0] + "/config.json");
    QVERIFY(config.contains("\"wind\""));
    QVERIFY(config.contains("\"drone.position_noise\""));  // a live change: in "changes"
  }
};

QTEST_MAIN(GuiEnvironment)
#include "gui_environment.moc"
