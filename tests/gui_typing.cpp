// The desktop typed into as a person types: every spin box and line of every page (sandbox, queue, map
// creator, the sweep dialog) gets a value typed and committed with Enter, with Tab and by clicking
// elsewhere. Nothing may crash (typing a forest map's size once deleted the spin box inside its own key
// press), and each value is either applied or refused with its message. Then the displays that misled:
// the full 64-bit seed, the map file in the map box, the queue's real count, results already in OUT,
// Plots in OUT/<test>/plots, another queue's folder refused as salsa run refuses it, --yes, a long
// status message beside the figures, the test's time, a session restored without its plugins.
#include "common.hpp"

#include <QAbstractSpinBox>
#include <QComboBox>
#include <QGroupBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QPointer>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QSignalSpy>
#include <QSlider>
#include <QSpinBox>
#include <QStatusBar>
#include <QTableView>
#include <QTemporaryDir>
#include <QWheelEvent>
#include <cmath>
#include <functional>

#include "main_window.hpp"
#include "map_editor.hpp"
#include "number_field.hpp"
#include "param_panel.hpp"
#include "queue_page.hpp"
#include "sandbox_page.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

enum class Commit { enter, tab, focus_loss };
const char* name_of(Commit c) { return c == Commit::enter ? "Enter" : c == Commit::tab ? "Tab" : "focus loss"; }

/// The inputs a person types into under `root`: spin boxes and lines (not a spin box's own line), enabled.
std::vector<QWidget*> inputs_of(QWidget* root) {
  std::vector<QWidget*> out;
  for (QWidget* w : root->findChildren<QWidget*>()) {
    if (!w->isEnabled() || !w->isVisibleTo(root)) continue;
    if (qobject_cast<QAbstractSpinBox*>(w)) out.push_back(w);
    else if (qobject_cast<QLineEdit*>(w) && !qobject_cast<QAbstractSpinBox*>(w->parentWidget()) && !qobject_cast<QComboBox*>(w->parentWidget()))
      out.push_back(w);
  }
  return out;
}

/// A value next to the current one, in range, as text typed into `w`.
QString next_value(QWidget* w) {
  if (auto* n = qobject_cast<NumberField*>(w)) {
    const Parameter& p = n->spec();
    const double step = p.is_integer() ? 1 : p.step > 0 ? p.step : 0.5;
    const double v = n->value() + step <= p.max ? n->value() + step : n->value() - step;
    return QString::fromStdString(Parameter::format(v));
  }
  auto* line = qobject_cast<QLineEdit*>(w);
  bool number = false;
  const qulonglong n = line->text().toULongLong(&number);
  return number ? QString::number(n + 1) : line->text() + "1";
}

/// Closes the refusals' message boxes (window-modal: they would take the next keys).
void close_message_boxes() {
  std::vector<QPointer<QMessageBox>> boxes;  // pointers that notice the boxes deleting themselves on close
  for (QWidget* w : QApplication::topLevelWidgets())
    if (auto* box = qobject_cast<QMessageBox*>(w); box && box->isVisible()) boxes.emplace_back(box);
  QPointer<QWidget> owner;
  for (auto& box : boxes)
    if (box) {
      if (box->parentWidget()) owner = box->parentWidget()->window();
      box->done(QMessageBox::Ok);
    }
  QApplication::processEvents();
  if (owner) {  // focus goes back to the window, as when a person clicks OK
    owner->activateWindow();
    (void)QTest::qWaitForWindowActive(owner);
  }
}

void type_commit_only(QWidget* w, Commit how, QWidget* elsewhere);

/// Types `text` into `w` (replacing what it shows) and commits it, as a person would.
void type_and_commit(QWidget* w, const QString& text, Commit how, QWidget* elsewhere) {
  w->setFocus(Qt::MouseFocusReason);
  QApplication::processEvents();
  if (auto* s = qobject_cast<QAbstractSpinBox*>(w)) s->selectAll();
  if (auto* l = qobject_cast<QLineEdit*>(w)) l->selectAll();
  QTest::keyClicks(w, text);
  type_commit_only(w, how, elsewhere);
}

/// Commits what was typed into `w`: Enter, Tab, or focus given to `elsewhere`.
void type_commit_only(QWidget* w, Commit how, QWidget* elsewhere) {
  QPointer<QWidget> alive(w);
  if (how == Commit::enter) QTest::keyClick(w, Qt::Key_Return);
  else if (how == Commit::tab) QTest::keyClick(w, Qt::Key_Tab);
  else elsewhere->setFocus(Qt::MouseFocusReason);
  QApplication::processEvents();
  if (alive && how != Commit::focus_loss) elsewhere->setFocus(Qt::MouseFocusReason);
  QApplication::processEvents();
  close_message_boxes();
}

/// What `w` shows now, as the text a person would read back (spin boxes without prefix and suffix).
QString shown(QWidget* w) {
  if (auto* n = qobject_cast<NumberField*>(w)) return QString::fromStdString(Parameter::format(n->value()));
  return qobject_cast<QLineEdit*>(w)->text();
}

constexpr const char* small_test = R"({"name": "typed", "behavior": "flocking", "drones": 6,
  "map": {"name": "forest", "params": {"size": 300}}, "targets": {"kind": "tree", "count": 30}, "time": 60, "seed": 3})";

}  // namespace

class GuiTyping : public QObject {
  Q_OBJECT
  std::shared_ptr<PluginHost> host_ = builtin_host();
  std::unique_ptr<MainWindow> window_;
  QTemporaryDir dir_;

  SandboxPage& sandbox() { return *window_->sandbox(); }
  void settle() {
    QApplication::processEvents();
    sandbox().poll();
    sandbox().engine().sync();
    sandbox().poll();
  }

  /// Types into every input of `root` with every commit; `check` says "" or what went wrong for one.
  void type_into_every_input(QWidget* root, QWidget* elsewhere, const std::function<void()>& after,
                             const std::function<QString()>& message) {
    int typed = 0;
    for (Commit how : {Commit::enter, Commit::tab, Commit::focus_loss}) {
      const auto count = inputs_of(root).size();
      QVERIFY2(count > 0, "no inputs found");
      for (std::size_t i = 0; i < count; ++i) {
        const auto now = inputs_of(root);  // rebuilt rows are found again by position
        if (i >= now.size()) break;
        QWidget* w = now[i];
        const QString name = w->objectName().isEmpty() ? QString(w->metaObject()->className()) : w->objectName();
        const QString text = next_value(w);
        const QString before_message = message();
        type_and_commit(w, text, how, elsewhere);
        after();
        ++typed;
        // Applied (the input shows it, found again by name if it was rebuilt), or refused with a message.
        QWidget* again = w;
        if (!w->objectName().isEmpty()) {
          again = nullptr;
          for (QWidget* c : inputs_of(root))
            if (c->objectName() == w->objectName()) again = c;
        }
        QVERIFY2(again, qPrintable(name + ": the input is gone after " + name_of(how)));
        const bool applied = shown(again) == text;
        const bool refused = message() != before_message && !message().isEmpty();
        QVERIFY2(applied || refused, qPrintable(QString("%1: typed %2, committed with %3: shows %4 and no message")
                                                    .arg(name, text, name_of(how), shown(again))));
      }
    }
    QVERIFY(typed >= 3);
  }

 private Q_SLOTS:
  void init() {
    QSettings().clear();
    window_ = std::make_unique<MainWindow>(host_, std::vector<std::filesystem::path>{});
    window_->queue_page()->set_salsa_program(salsa_executable());
    window_->resize(1400, 900);
    window_->show();
    window_->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    QVERIFY(sandbox().open_test_spec(parse_test(small_test, "typed", *host_)).empty());
  }
  void cleanup() { window_.reset(); }

  // The crash as found: a forest's size and clusters typed, committed three ways.
  void typing_the_forest_size_and_clusters() {
    for (Commit how : {Commit::enter, Commit::tab, Commit::focus_loss}) {
      const int size = how == Commit::enter ? 800 : how == Commit::tab ? 650 : 420;
      type_and_commit(sandbox().map_panel()->spin_box("size"), QString::number(size), how, sandbox().view());
      settle();
      QCOMPARE(sandbox().engine().current_test()->map.params.get("size"), double(size));
      QCOMPARE(sandbox().map_panel()->value("size"), double(size));
      type_and_commit(sandbox().map_panel()->spin_box("clusters"), "12", how, sandbox().view());
      settle();
      QCOMPARE(sandbox().engine().current_test()->map.params.get("clusters"), 12.0);
      type_and_commit(sandbox().map_panel()->spin_box("clusters"), "0", how, sandbox().view());
      settle();
    }
    // Typed one key at a time, the world is rebuilt once per value, not per keystroke.
    QCOMPARE(sandbox().engine().current_test()->map.params.get("size"), 420.0);
  }

  void every_sandbox_input() {
    type_into_every_input(sandbox().controls(), sandbox().view(), [this] { settle(); }, [this] { return sandbox().last_message(); });
    // And what it typed ran: the last value of each start-state field is the engine's.
    const auto t = sandbox().engine().current_test();
    QCOMPARE(sandbox().map_panel()->value("size"), t->map.params.get("size"));
    QCOMPARE(QString::number(t->seed), sandbox().seed_box()->text());
    QCOMPARE(sandbox().targets_box()->value(), static_cast<double>(t->targets));
    QCOMPARE(sandbox().drones_box()->value(), static_cast<double>(t->groups[0].drones));
  }

  void refused_values_say_why() {
    // A speed the physics refuses: the message, and the box back at what runs.
    auto* speed = sandbox().drone_panel()->spin_box("max_speed");
    type_and_commit(speed, "100", Commit::enter, sandbox().view());
    settle();
    close_message_boxes();
    QVERIFY2(sandbox().last_message().startsWith("drone.max_speed: 100 m/s"), qPrintable(sandbox().last_message()));
    QCOMPARE(sandbox().drone_panel()->value("max_speed"), sandbox().engine().current_test()->groups[0].drone.max_speed);
    // A seed that is not one: the line's message, the seed that runs shown again.
    for (const char* bad : {"abc", "9007199254740993", "-1", "1e5"}) {
      type_and_commit(sandbox().seed_box(), bad, Commit::tab, sandbox().view());
      settle();
      QVERIFY2(sandbox().last_message().startsWith("seed: \"" + QString(bad) + "\" is not a seed (allowed: whole number in [0, 9007199254740992])"),
               qPrintable(sandbox().last_message()));
      QCOMPARE(sandbox().seed_box()->text(), QString("3"));
    }
  }

  // Every number field takes what a test file takes, typed with keys: scientific notation and the full
  // range applied exactly; too large, letters, a comma or a fraction refused in one line naming the
  // field and its range, the field back at what runs. Never a silent change.
  void typed_numbers_are_taken_as_a_test_file_takes_them() {
    struct Case {
      NumberField* field;
      const char* typed;
      double applied;        // NAN: refused, the value before kept
      const char* refusal;   // "" when applied, else the start of the status line
    };
    sandbox().model_box("comm")->setChecked(true);
    settle();
    NumberField* size = sandbox().map_panel()->spin_box("size");
    NumberField* drones = sandbox().drones_box();
    NumberField* targets = sandbox().targets_box();
    NumberField* loss = sandbox().model_panel("comm")->spin_box("loss");
    const Case cases[] = {
        {size, "1e308", NAN, "size: \"1e308\" is out of range (allowed: ["},
        {size, "4E2", 400, ""},
        {loss, "1e-3", 0.001, ""},
        {drones, "1000001", NAN, "drones: \"1000001\" is out of range (allowed: whole number in [1, 1000000])"},
        {drones, "1,5", NAN, "drones: \"1,5\" is not a number (allowed: whole number in [1, 1000000])"},
        {drones, "2.5", NAN, "drones: \"2.5\" is not a whole number (allowed: whole number in [1, 1000000])"},
        {drones, "abc", NAN, "drones: \"abc\" is not a number"},
        {drones, "1.2e1", 12, ""},
        {targets, "99999999", NAN, "targets: \"99999999\" is out of range (allowed: whole number in [0, 10000000])"},
        {targets, "1.5e3", 1500, ""},
    };
    for (Commit how : {Commit::enter, Commit::tab, Commit::focus_loss})
      for (const Case& c : cases) {
        // A field rebuilt by a reload is found again by name.
        NumberField* field = c.field == size ? sandbox().map_panel()->spin_box("size")
                             : c.field == loss ? sandbox().model_panel("comm")->spin_box("loss") : c.field;
        const double before = field->value();
        QSignalSpy refused(field, &NumberField::refused);
        type_and_commit(field, c.typed, how, sandbox().view());
        settle();
        if (c.field == size) field = sandbox().map_panel()->spin_box("size");
        if (c.field == loss) field = sandbox().model_panel("comm")->spin_box("loss");
        const QString what = QString("%1 typed into %2, %3").arg(c.typed, field->objectName(), name_of(how));
        const double expected = std::isnan(c.applied) ? before : c.applied;
        QVERIFY2(field->value() == expected, qPrintable(what + QString(": holds %1").arg(field->value(), 0, 'g', 17)));
        if (*c.refusal) {
          QVERIFY2(refused.count() == 1, qPrintable(what + QString(": %1 refusals").arg(refused.count())));
          QVERIFY2(window_->status_text().startsWith(c.refusal), qPrintable(what + ": says " + window_->status_text()));
          QVERIFY2(!window_->status_text().contains('\n'), qPrintable(what + ": more than one line"));
        } else {
          QVERIFY2(refused.isEmpty(), qPrintable(what + ": refused: " + window_->status_text()));
          QCOMPARE(field->text(), QString::fromStdString(Parameter::format(c.applied) + (field->spec().unit.empty() ? "" : " " + field->spec().unit)));
        }
      }
    // What was applied is what runs.
    QCOMPARE(sandbox().engine().current_test()->targets, std::size_t(1500));
    QCOMPARE(sandbox().engine().current_test()->groups[0].drones, std::size_t(12));
    QCOMPARE(sandbox().engine().current_test()->map.params.get("size"), 400.0);
    QCOMPARE(sandbox().engine().current_test()->comm.loss, 0.001);
  }

  // The queue's number cells read what is typed as a test file's number: 1e9 s is not 19 s, and a
  // seed past 2^53 is refused, not rounded into range.
  void queue_cells_take_a_test_files_numbers() {
    window_->set_mode(MainWindow::Mode::queue);
    QueuePage* page = window_->queue_page();
    QVERIFY(page->add_from_sandbox().empty());
    QTableView* table = page->table();
    auto type_cell = [&](int col, const QString& text) {
      const QModelIndex at = page->model()->index(0, col);
      table->setFocus();
      table->setCurrentIndex(at);
      QTest::keyClick(table, Qt::Key_F2);
      QApplication::processEvents();
      QWidget* editor = QApplication::focusWidget();
      QVERIFY(qobject_cast<QLineEdit*>(editor));
      qobject_cast<QLineEdit*>(editor)->selectAll();
      QTest::keyClicks(editor, text);
      type_commit_only(editor, Commit::enter, page->findChild<QPlainTextEdit*>());
    };
    type_cell(QueueModel::col_time, "1.5e3");
    QCOMPARE(page->model()->test(0).time, 1500.0);
    type_cell(QueueModel::col_time, "1e9");
    QVERIFY2(page->model()->test(0).time == 1e9 || page->last_message().contains("time"), qPrintable(page->last_message()));
    QVERIFY(page->model()->test(0).time == 1e9 || page->model()->test(0).time == 1500.0);
    const auto seed = page->model()->test(0).seed;
    type_cell(QueueModel::col_seed, "9007199254740993");
    QCOMPARE(page->model()->test(0).seed, seed);
    QVERIFY2(page->last_message().contains("seed: 9007199254740993 is out of range (allowed: whole number in [0, 9007199254740992])"),
             qPrintable(page->last_message()));
    close_message_boxes();
  }

  void every_queue_input() {
    window_->set_mode(MainWindow::Mode::queue);
    QueuePage* page = window_->queue_page();
    type_into_every_input(page, page->table(), [] {}, [page] { return page->last_message(); });
    // The table's editable cells, typed into as a person does: F2 opens the editor.
    QVERIFY(page->add_from_sandbox().empty());
    QTableView* table = page->table();
    QWidget* elsewhere = page->findChild<QPlainTextEdit*>();
    QVERIFY(elsewhere);
    int round = 0;
    for (Commit how : {Commit::enter, Commit::tab, Commit::focus_loss})
      for (int col : {QueueModel::col_name, QueueModel::col_drones, QueueModel::col_targets, QueueModel::col_time, QueueModel::col_seed}) {
        ++round;
        const QModelIndex at = page->model()->index(0, col);
        const QString text = col == QueueModel::col_name    ? QString("typed-%1").arg(round)
                             : col == QueueModel::col_seed  ? QString::number(4746454603967234LL + round)
                             : col == QueueModel::col_time  ? QString::number(30 + round)
                                                            : QString::number(page->model()->data(at).toLongLong() + 1);
        table->setFocus();
        table->setCurrentIndex(at);
        QTest::keyClick(table, Qt::Key_F2);
        QApplication::processEvents();
        QWidget* editor = QApplication::focusWidget();
        QVERIFY2(editor && editor != table, qPrintable(QString("no editor for column %1").arg(col)));
        const QString before = page->last_message();
        if (auto* line = qobject_cast<QLineEdit*>(editor)) line->selectAll();
        if (auto* spin = qobject_cast<QAbstractSpinBox*>(editor)) spin->selectAll();
        QTest::keyClicks(editor, text);
        type_commit_only(editor, how, elsewhere);
        const QString now = page->model()->data(page->model()->index(0, col), Qt::EditRole).toString();
        QVERIFY2(now == text || (page->last_message() != before && !page->last_message().isEmpty()),
                 qPrintable(QString("column %1: typed %2 (%3), shows %4").arg(col).arg(text, name_of(how), now)));
      }
    // The last round (focus loss) applied each cell: the seed exactly, past 2^52.
    QCOMPARE(page->model()->test(0).name, std::string("typed-11"));
    QCOMPARE(page->model()->test(0).seed, std::uint64_t(4746454603967234LL + 15));
    // Text that is no number is refused with its message, not read as 0.
    const QModelIndex seed = page->model()->index(0, QueueModel::col_seed);
    const auto kept = page->model()->test(0).seed;
    QVERIFY(!page->model()->setData(seed, QString("abc")));
    QVERIFY2(page->last_message().contains("seed: \"abc\" is not a number"), qPrintable(page->last_message()));
    QCOMPARE(page->model()->test(0).seed, kept);
    close_message_boxes();
    // The sweep dialog's lines and boxes: each typed value recounts the sweep, never crashes.
    SweepDialog sweep(host_, parse_test(small_test, "typed", *host_));
    sweep.show();
    sweep.activateWindow();  // focus moves within the window a person types into
    QVERIFY(QTest::qWaitForWindowActive(&sweep));
    auto* other = new QPushButton("elsewhere", &sweep);
    other->show();  // a child added to a shown dialog is hidden until shown: focus could not go there
    type_into_every_input(&sweep, other, [] {}, [&sweep] { return sweep.count_label()->text(); });
    // The queue seed takes the whole range, exactly; anything else is refused in the count line.
    sweep.seed()->setText("4746454603967234");
    std::string why;
    QVERIFY2(QString::fromStdString(sweep.queue_json(&why)).contains("\"seed\": 4746454603967234"), why.c_str());
    QVERIFY2(sweep.count_label()->text().contains("tests"), qPrintable(sweep.count_label()->text()));
    sweep.seed()->setText("12x");
    QVERIFY2(sweep.count_label()->text().contains("queue seed: \"12x\" is not a seed"), qPrintable(sweep.count_label()->text()));
    sweep.seed()->setText("9007199254740993");
    QVERIFY2(sweep.count_label()->text().contains("seed"), qPrintable(sweep.count_label()->text()));
    QVERIFY(!sweep.count_label()->text().contains("makes"));
  }

  void every_map_creator_input() {
    window_->set_mode(MainWindow::Mode::map_creator);
    MapEditor* editor = window_->map_editor();
    type_into_every_input(editor, editor->canvas(), [] {}, [editor] { return editor->last_message(); });
  }

  void a_large_seed_round_trips() {
    const QString big = "4746454603967234";
    type_and_commit(sandbox().seed_box(), big, Commit::enter, sandbox().view());
    settle();
    QCOMPARE(sandbox().engine().current_test()->seed, std::uint64_t{4746454603967234});
    QCOMPARE(sandbox().seed_box()->text(), big);
    // Saved as a test, read back: the same seed, and shown in full after "Load into sandbox".
    const QString file = dir_.filePath("seeded.json");
    QCOMPARE(sandbox().save_test(file), std::string());
    TestSpec back = load_tests(file.toStdString(), *host_).front();
    QCOMPARE(back.seed, std::uint64_t{4746454603967234});
    QVERIFY(sandbox().open_test_spec(parse_test(small_test, "typed", *host_)).empty());
    QCOMPARE(sandbox().seed_box()->text(), QString("3"));
    QueuePage* page = window_->queue_page();
    back.changes.clear();
    QVERIFY(page->model()->add({back}).empty());
    window_->set_mode(MainWindow::Mode::queue);
    page->table()->selectRow(0);
    for (auto* b : page->findChildren<QPushButton*>())
      if (b->text() == "Load into sandbox") b->click();
    QCOMPARE(window_->mode(), MainWindow::Mode::sandbox);
    QCOMPARE(sandbox().seed_box()->text(), big);
    QCOMPARE(sandbox().engine().current_test()->seed, std::uint64_t{4746454603967234});
    // The largest seed salsa takes, 2^53.
    type_and_commit(sandbox().seed_box(), "9007199254740992", Commit::enter, sandbox().view());
    settle();
    QCOMPARE(sandbox().engine().current_test()->seed, std::uint64_t{9007199254740992});
  }

  void the_map_box_names_the_map_file() {
    const QString map = q(source_dir() / "examples/maps/warehouse.json");
    QVERIFY2(QFileInfo::exists(map), qPrintable(map));
    QVERIFY(sandbox().open_map(map).empty());
    QCOMPARE(sandbox().map_box()->currentText(), QString("map file: warehouse.json"));
    QVERIFY(sandbox().map_box()->findText("forest") >= 0);
    // Choosing a generated map again leaves the file.
    sandbox().map_box()->setCurrentText("forest");
    settle();
    QCOMPARE(sandbox().engine().current_test()->map.name, std::string("forest"));
    QCOMPARE(sandbox().map_box()->findText("map file: warehouse.json"), -1);
  }

  void sliders_are_fine_over_decades() {
    ParamPanel* drone = sandbox().drone_panel();
    // detection range 0–100 km (the test format's range, drone_schema): logarithmic, so the slider's
    // middle is hundreds of metres, not 50 km, and one position (an arrow key) moves it by about 1 %.
    QVERIFY(drone->slider_value("detection_range", 500) < 1000);
    for (int s : {100, 500, 900}) {
      const double a = drone->slider_value("detection_range", s), b = drone->slider_value("detection_range", s + 1);
      QVERIFY2(b - a <= 0.02 * b + 0.5, qPrintable(QString("%1 -> %2").arg(a).arg(b)));
    }
    // The map's size, 50 m to 100 km: 16 positions from 300 m stay within 300 ± 20 %.
    QSlider* size = sandbox().map_panel()->slider("size");
    const int at = size->value();
    QVERIFY(std::abs(sandbox().map_panel()->slider_value("size", at + 16) - 300) < 60);
    // Every slider's ends are its range's, and its value round-trips within one step.
    for (ParamPanel* panel : {sandbox().behavior_panel(), drone, sandbox().map_panel()})
      for (const Parameter& p : panel->schema()) {
        QSlider* s = panel->slider(p.name);
        QCOMPARE(panel->slider_value(p.name, s->minimum()), p.min);
        QCOMPARE(panel->slider_value(p.name, s->maximum()), p.max);
      }
  }

  // The wheel scrolls the panel: it edits a spin box, slider or combo box only once it is clicked
  // into (a person scrolling down once set the camera range they scrolled past).
  void the_wheel_scrolls_the_panel_not_its_values() {
    settle();
    auto* area = qobject_cast<QScrollArea*>(sandbox().controls());
    QVERIFY(area);
    auto wheel = [](QWidget* w) {
      QWheelEvent down(QPointF(5, 5), w->mapToGlobal(QPointF(5, 5)), {}, QPoint(0, -120), Qt::NoButton, {}, Qt::NoScrollPhase, false);
      QApplication::sendEvent(w, &down);
      QApplication::processEvents();
    };
    ParamPanel* drone = sandbox().drone_panel();
    const double range = drone->value("camera_range");
    const int scrolled = area->verticalScrollBar()->value();
    for (QWidget* w : std::initializer_list<QWidget*>{drone->spin_box("camera_range"), drone->slider("camera_range"), sandbox().behavior_box()})
      wheel(w);
    settle();
    QCOMPARE(drone->value("camera_range"), range);
    QCOMPARE(sandbox().behavior_box()->currentText(), QString("flocking"));
    QVERIFY(area->verticalScrollBar()->value() > scrolled);
    QCOMPARE(sandbox().engine().timeline().size(), std::size_t(0));
    // Clicked into, it takes the wheel.
    drone->spin_box("camera_range")->setFocus(Qt::MouseFocusReason);
    wheel(drone->spin_box("camera_range"));
    settle();
    QVERIFY(drone->value("camera_range") < range);
  }

  void a_long_message_never_runs_into_the_figures() {
    settle();
    QTest::qWait(400);  // the figures are written a few times a second
    const QString text = "a very long message " + QString("that goes on and on ").repeated(40) + "END";
    sandbox().open_test("/no/such/file-" + QString("x").repeated(300) + ".json");
    window_->statusBar()->adjustSize();
    QApplication::processEvents();
    const QString full = window_->status_text();
    QVERIFY(full.contains("/no/such/file-"));
    QCOMPARE(window_->status_line()->toolTip(), full);
    QVERIFY(window_->status_line()->text().size() < full.size());  // elided
    QVERIFY(window_->status_line()->text().endsWith(QChar(0x2026)));
    const QRect line = window_->status_line()->geometry();
    for (QLabel* figure : sandbox().status_labels())
      if (figure->isVisible()) QVERIFY2(!line.intersects(figure->geometry()), qPrintable(figure->text()));
    Q_UNUSED(text);
  }

  void the_sandbox_stops_at_the_tests_time() {
    auto t = parse_test(small_test, "typed", *host_);
    t.time = 0.5;
    QVERIFY(sandbox().open_test_spec(t).empty());
    sandbox().start();
    QTRY_VERIFY_WITH_TIMEOUT(sandbox().last_message().startsWith("paused at t = "), 20000);
    QVERIFY2(sandbox().last_message().startsWith("paused at t = 0.5 s, the test's time"), qPrintable(sandbox().last_message()));
    sandbox().engine().sync();
    QTRY_VERIFY_WITH_TIMEOUT(sandbox().engine().snapshot()->state == RunState::paused, 5000);
    const double stopped = sandbox().engine().snapshot()->time;
    QCOMPARE(sandbox().engine().snapshot()->step, std::uint64_t(30));  // the step that reached 0.5 s, not one more
    // Start again: it runs on past the time, and the status bar says so.
    sandbox().start();
    QTRY_VERIFY_WITH_TIMEOUT(sandbox().engine().snapshot()->time > stopped + 0.2, 20000);
    QTRY_VERIFY_WITH_TIMEOUT(sandbox().time_label()->text().contains("past the test's 0.5 s"), 5000);
    QCOMPARE(sandbox().engine().snapshot()->state, RunState::running);
    sandbox().pause();
  }

  void a_session_its_plugins_are_missing_for_says_so() {
    window_.reset();
    QSettings().setValue("sandbox/test", R"({"name": "mine", "behavior": "my_own_behavior", "drones": 5, "time": 10})");
    window_ = std::make_unique<MainWindow>(host_, std::vector<std::filesystem::path>{});
    const QString said = window_->status_text();
    QVERIFY2(said.contains("the last session's test (behavior 'my_own_behavior') was not restored") && said.contains("--plugin-dir"),
             qPrintable(said));
    QCOMPARE(window_->sandbox()->engine().current_test()->groups[0].behavior.name, std::string("pheromone_avoidance"));
  }
};

QTEST_MAIN(GuiTyping)
#include "gui_typing.moc"
