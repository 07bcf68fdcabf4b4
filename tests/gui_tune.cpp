// Tune mode as a person uses it: the sandbox's test taken, numbers ticked and ranges typed into the
// table, bad values refused with one line before anything runs; a run of salsa tune in the background
// draws its chart while it runs and writes what `salsa tune` of the saved file writes; the same folder
// resumes, another tune's folder is refused; the winner goes into the sandbox.
#include "common.hpp"

#include <QApplication>
#include <QComboBox>
#include <QLineEdit>
#include <QLineSeries>
#include <QProcess>
#include <QProgressBar>
#include <QPushButton>
#include <QScatterSeries>
#include <QSettings>
#include <QSpinBox>
#include <QTableWidget>
#include <nlohmann/json.hpp>

#include "main_window.hpp"
#include "number_field.hpp"
#include "tune_page.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

constexpr const char* sandbox_test = R"({"name": "sandbox", "behavior": "flocking", "drones": 4,
  "map": {"name": "empty", "params": {"size": 150}}, "targets": {"kind": "tree", "count": 30}, "time": 4, "seed": 9})";

int row_of(QTableWidget* t, const QString& key) {
  for (int r = 0; r < t->rowCount(); ++r)
    if (t->item(r, 0)->text() == key) return r;
  return -1;
}

/// Types `text` into cell (row, column) as a person does: F2, select all, keys, Enter.
void type_cell(QTableWidget* t, int row, int column, const QString& text) {
  t->setFocus();
  t->setCurrentCell(row, column);
  QTest::keyClick(t, Qt::Key_F2);
  QApplication::processEvents();
  QWidget* editor = QApplication::focusWidget();
  QVERIFY2(editor && editor != t, "no editor opened");
  if (auto* line = qobject_cast<QLineEdit*>(editor)) line->selectAll();
  QTest::keyClicks(editor, text);
  QTest::keyClick(editor, Qt::Key_Return);
  QApplication::processEvents();
}

void type_into(QWidget* w, const QString& text) {
  w->setFocus();
  if (auto* line = qobject_cast<QLineEdit*>(w)) line->selectAll();
  if (auto* spin = qobject_cast<QAbstractSpinBox*>(w)) spin->selectAll();
  QTest::keyClicks(w, text);
  QTest::keyClick(w, Qt::Key_Tab);
}

}  // namespace

class GuiTune : public QObject {
  Q_OBJECT
  std::shared_ptr<PluginHost> host_ = builtin_host();
  std::optional<TestSpec> loaded_;

  std::unique_ptr<TunePage> page() {
    auto p = std::make_unique<TunePage>(host_, std::vector<std::filesystem::path>{});
    p->set_salsa_program(salsa_executable());
    p->set_sandbox([this](std::string*) -> std::optional<TestSpec> { return parse_test(sandbox_test, "sandbox", *host_); });
    p->set_load_into_sandbox([this](const TestSpec& t) { loaded_ = t; });
    return p;
  }

  /// A small, quick tune: flocking's separation distance and cohesion weight, random search.
  std::unique_ptr<TunePage> small_tune() {
    auto p = page();
    p->resize(1200, 800);
    p->show();
    if (!p->from_sandbox().empty()) return nullptr;
    QTableWidget* t = p->parameters();
    for (int r = 0; r < t->rowCount(); ++r) t->item(r, 0)->setCheckState(Qt::Unchecked);
    p->set_parameter("behavior.params.separation_distance", true);
    p->set_parameter("behavior.params.cohesion_weight", true);
    type_cell(t, row_of(t, "behavior.params.separation_distance"), 2, "5");
    type_cell(t, row_of(t, "behavior.params.separation_distance"), 3, "80");
    p->algorithm_box()->setCurrentText("random");
    type_into(p->evaluations_box(), "12");
    type_into(p->worlds_box(), "2");
    type_into(p->validation_box(), "2");
    type_into(p->seed_box(), "5");
    p->jobs_box()->setValue(2);
    return p;
  }

 private Q_SLOTS:
  void init() { QSettings().clear(); }

  void the_table_lists_the_tests_numbers_with_their_declared_ranges() {
    auto p = page();
    QVERIFY(p->from_sandbox().empty());
    QTableWidget* t = p->parameters();
    // The behavior's parameters are ticked, the rest offered unticked, each with its declaration.
    for (const Parameter& param : host_->behavior("flocking").factory.parameters) {
      const int r = row_of(t, q("behavior.params." + param.name));
      QVERIFY2(r >= 0, param.name.c_str());
      QCOMPARE(t->item(r, 0)->checkState(), Qt::Checked);
      QCOMPARE(t->item(r, 2)->text(), q(Parameter::format(param.min)));
      QCOMPARE(t->item(r, 3)->text(), q(Parameter::format(param.max)));
      QCOMPARE(t->item(r, 5)->text(), q(param.range()));
    }
    for (const char* key : {"drones", "drone.max_speed", "targets.count", "map.params.size"}) {
      const int r = row_of(t, key);
      QVERIFY2(r >= 0, key);
      QCOMPARE(t->item(r, 0)->checkState(), Qt::Unchecked);
    }
    QCOMPARE(t->item(row_of(t, "drones"), 1)->text(), QString("4"));
    // A wide positive range is searched on a log scale unless unticked (docs/tuning.md's rule).
    QCOMPARE(t->item(row_of(t, "drone.max_speed"), 4)->checkState(), Qt::Checked);
    QCOMPARE(t->item(row_of(t, "behavior.params.cohesion_weight"), 4)->checkState(), Qt::Unchecked);
    QVERIFY(p->objective_box()->findText("targets_found") >= 0);
    QCOMPARE(p->objective_box()->currentText(), QString("targets_found"));
    // The tune file the page writes reads back with the ticked keys and the typed range only.
    std::string why;
    const auto text = p->tune_json(&why);
    QVERIFY2(!text.empty(), why.c_str());
    const auto j = nlohmann::json::parse(text);
    QCOMPARE(j["parameters"].size(), host_->behavior("flocking").factory.parameters.size());
    QCOMPARE(j["parameters"]["behavior.params.cohesion_weight"].dump(), std::string("{}"));
    QVERIFY(!j["test"].contains("seed"));
  }

  void bad_values_are_refused_with_one_line_before_anything_runs() {
    auto p = page();
    p->show();
    QVERIFY(p->from_sandbox().empty());
    QTableWidget* t = p->parameters();
    const int r = row_of(t, "behavior.params.cohesion_weight");
    std::string why;
    type_cell(t, r, 2, "abc");
    QVERIFY(p->tune_json(&why).empty());
    QCOMPARE(why, std::string("tune: behavior.params.cohesion_weight: min \"abc\" is not a number (allowed: [0, 10])"));
    type_cell(t, r, 2, "-1");
    QVERIFY(p->tune_json(&why).empty());
    QVERIFY2(why.find("parameters.behavior.params.cohesion_weight.min: -1 is outside the declared range (allowed: [0, 10])") != std::string::npos,
             why.c_str());
    QVERIFY2(why.find('\n') == std::string::npos, why.c_str());
    type_cell(t, r, 2, "7");
    type_cell(t, r, 3, "7");
    QVERIFY(p->tune_json(&why).empty());
    QVERIFY2(why.find("is an empty range") != std::string::npos, why.c_str());
    type_cell(t, r, 3, "9");
    QVERIFY2(!p->tune_json(&why).empty(), why.c_str());
    for (int i = 0; i < t->rowCount(); ++i) t->item(i, 0)->setCheckState(Qt::Unchecked);
    QVERIFY(p->tune_json(&why).empty());
    QCOMPARE(why, std::string("tune: nothing to tune (allowed: tick one or more numbers in the table)"));
    p->set_parameter("behavior.params.cohesion_weight", true);
    type_into(p->seed_box(), "x1");
    QVERIFY(p->tune_json(&why).empty());
    QVERIFY2(why.find("seed: \"x1\" is not a seed") != std::string::npos, why.c_str());
    // Run refuses too, and starts nothing.
    QTemporaryDir dir;
    QVERIFY(!p->run(dir.filePath("out")).empty());
    QVERIFY(!p->running());
    QVERIFY(!QFileInfo::exists(dir.filePath("out")));
  }

  void a_run_draws_its_chart_and_writes_what_salsa_tune_writes() {
    auto p = small_tune();
    QVERIFY(p);
    QTemporaryDir dir;
    const QString out = dir.filePath("tuned");
    QVERIFY(p->run(out).empty());
    QVERIFY(p->running());
    QVERIFY2(p->wait(120000), qPrintable(p->log_text()));
    QVERIFY2(QFileInfo::exists(out + "/best.json"), qPrintable(p->log_text()));
    QVERIFY2(p->last_message().startsWith("tune finished"), qPrintable(p->last_message()));
    // The chart: the defaults' level, every complete candidate, the best so far never worse.
    QCOMPARE(p->defaults_series()->count(), 2);
    QVERIFY(p->candidates_series()->count() >= 2);
    QVERIFY(p->best_series()->count() >= 2);
    for (int i = 1; i < p->best_series()->count(); ++i) QVERIFY(p->best_series()->at(i).y() >= p->best_series()->at(i - 1).y());
    QVERIFY(p->progress()->value() > 0 && p->progress()->value() <= 12);
    QVERIFY(p->load_best_button()->isEnabled());
    // The saved file, run by salsa tune itself, gives the same tune.csv.
    QProcess cli;
    cli.start(salsa_executable(), {"tune", out + ".tune.json", "--out", dir.filePath("cli"), "--jobs", "1", "--no-plots", "--quiet"});
    QVERIFY(cli.waitForFinished(120000));
    QCOMPARE(cli.exitCode(), 0);
    QCOMPARE(read_file(dir.filePath("cli") + "/tune.csv"), read_file(out + "/tune.csv"));
    // The winner into the sandbox: best.json's test.
    QVERIFY(p->load_best().empty());
    QVERIFY(loaded_);
    const auto best = load_tests((out + "/best.json").toStdString(), *host_);
    QCOMPARE(resolved_json(*loaded_, *host_), resolved_json(best.front(), *host_));
    // Run again into the same folder: resumed, the same files; other settings: refused, nothing run.
    const QByteArray tune_csv = read_file(out + "/tune.csv");
    QVERIFY(p->run(out).empty());
    QVERIFY(p->log_text().contains("--resume"));
    QVERIFY(p->wait(120000));
    QCOMPARE(read_file(out + "/tune.csv"), tune_csv);
    const QByteArray saved = read_file(out + ".tune.json");
    type_into(p->evaluations_box(), "14");
    const std::string why = p->run(out);
    QVERIFY2(why.find("holds another tune") != std::string::npos, why.c_str());
    QVERIFY(!p->running());
    QCOMPARE(read_file(out + "/tune.csv"), tune_csv);
    QCOMPARE(read_file(out + ".tune.json"), saved);  // the tune file beside the folder is kept too
  }

  void open_results_shows_a_finished_tune() {
    auto p = small_tune();
    QVERIFY(p);
    QTemporaryDir dir;
    QVERIFY(p->run(dir.filePath("t")).empty());
    QVERIFY(p->wait(120000));
    auto other = page();
    QVERIFY(!other->open_results(dir.path()).empty());  // no tune there
    QVERIFY(other->open_results(dir.filePath("t")).empty());
    QCOMPARE(other->best_series()->count(), p->best_series()->count());
    QCOMPARE(other->defaults_series()->at(0).y(), p->defaults_series()->at(0).y());
    QVERIFY(other->load_best_button()->isEnabled());
  }

  void the_window_switches_to_tune_mode_with_the_sandboxs_test() {
    MainWindow w(*host_);
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    QTest::keyClick(&w, Qt::Key_4, Qt::ControlModifier);
    QCOMPARE(w.mode(), MainWindow::Mode::tune);
    QVERIFY(w.tune_page()->isVisible());
    QVERIFY(w.tune_page()->parameters()->rowCount() > 0);
    const auto current = w.sandbox()->engine().current_test();
    QVERIFY(current);
    const int r = row_of(w.tune_page()->parameters(), "drones");
    QCOMPARE(w.tune_page()->parameters()->item(r, 1)->text(), QString::number(current->groups.front().drones));
    QCOMPARE(w.windowTitle(), QString("salsa — tune"));
  }
};

QTEST_MAIN(GuiTune)
#include "gui_tune.moc"
