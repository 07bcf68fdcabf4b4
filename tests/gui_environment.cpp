// Communication (and the models beside it) in the desktop, as a person uses them: ticking
// "Communication" starts the test over with a radio; a value typed into its panel is a recorded live
// change; View → Communication links draws who hears whom; the inspector lists what a drone hears;
// a saved test replays the radio with salsa run.
#include "common.hpp"

#include <QAbstractSpinBox>
#include <QGroupBox>
#include <QSettings>
#include <QTemporaryDir>
#include <algorithm>

#include "main_window.hpp"
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
};

QTEST_MAIN(GuiEnvironment)
#include "gui_environment.moc"
