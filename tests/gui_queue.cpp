// Queue mode as a person uses it: tests added from the sandbox and from a sweep, edited, reordered,
// removed, saved and loaded; the file is one `salsa run` accepts and expands to the same tests; a
// queue run from the GUI writes what `salsa run` of the saved file writes; modes keep their state.
#include "common.hpp"

#include <QAbstractItemView>

#include <QFileInfo>

#include <QDir>

#include <QTimer>

#include <QFileDialog>

#include <QAbstractItemModelTester>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QProgressBar>
#include <QSettings>
#include <QSpinBox>
#include <QTableView>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include <QPushButton>
#include <QUndoStack>

#include "main_window.hpp"
#include "save_checked.hpp"
#include "number_field.hpp"
#include "map_editor.hpp"
#include "queue_page.hpp"
#include "salsa/core/experiments/queue.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

constexpr const char* sandbox_test = R"({"name": "sandbox", "behavior": "random_walk", "drones": 4,
  "map": {"name": "empty", "params": {"size": 200}}, "targets": {"kind": "tree", "count": 20}, "time": 3, "seed": 9})";

std::vector<std::string> resolved(const std::vector<TestSpec>& tests, const PluginHost& host) {
  std::vector<std::string> out;
  for (const auto& t : tests) out.push_back(resolved_json(t, host));
  return out;
}

std::vector<std::string> rows(const QueueModel& m, const PluginHost& host) {
  std::vector<std::string> out;
  for (int i = 0; i < m.rowCount(); ++i) out.push_back(resolved_json(m.test(i), host));
  return out;
}

}  // namespace

class GuiQueue : public QObject {
  Q_OBJECT
  std::shared_ptr<PluginHost> host_ = builtin_host();
  QTemporaryDir dir_;

  std::unique_ptr<QueuePage> page() {
    auto p = std::make_unique<QueuePage>(host_, std::vector<std::filesystem::path>{});
    p->set_salsa_program(salsa_executable());
    p->set_sandbox([this](std::string*) -> std::optional<TestSpec> { return parse_test(sandbox_test, "sandbox", *host_); });
    return p;
  }

 private Q_SLOTS:
  void init() { QSettings().clear(); }

  void the_model_passes_the_item_model_tester() {
    auto p = page();
    QAbstractItemModelTester tester(p->model(), QAbstractItemModelTester::FailureReportingMode::QtTest);
    QVERIFY(p->add_from_sandbox().empty());
    QVERIFY(p->add_from_sandbox().empty());
    QVERIFY(p->add_from_sandbox().empty());
    QVERIFY(p->model()->move(0, 1));
    QVERIFY(p->model()->move(2, -2));
    QVERIFY(!p->model()->move(0, -1));
    QVERIFY(p->model()->setData(p->model()->index(1, QueueModel::col_drones), 7));
    QVERIFY(p->model()->removeRow(1));
    QVERIFY(p->open(q(source_dir() / "examples/sweep-queue.json")).empty());
    QCOMPARE(p->model()->rowCount(), 12);
    p->model()->set_status(3, QueueModel::Status::failed, "why");
  }

  void add_sweep_reorder_remove_save_load_round_trip() {
    auto p = page();
    QVERIFY(p->add_from_sandbox().empty());
    QVERIFY(p->add_from_sandbox().empty());  // the same test again gets its own name
    QCOMPARE(p->model()->test(1).name, std::string("sandbox-2"));
    p->model()->setData(p->model()->index(1, QueueModel::col_seed), 10);  // else the same test twice

    SweepDialog sweep(host_, parse_test(sandbox_test, "sandbox", *host_));
    for (int i = 0; i < sweep.behaviors()->count(); ++i) {
      const QString b = sweep.behaviors()->item(i)->text();
      sweep.behaviors()->item(i)->setCheckState(b == "random_walk" || b == "flocking" ? Qt::Checked : Qt::Unchecked);
    }
    sweep.set_axis(0, "flocking.cohesion_weight", "1, 2");
    sweep.drones()->setText("3, 5");
    sweep.repeats()->setValue(2);
    // (random walk + flocking × 2 values) × 2 swarm sizes × 2 repeats
    QVERIFY2(sweep.count_label()->text().contains("<b>12</b>"), qPrintable(sweep.count_label()->text()));
    sweep.set_axis(1, "flocking.cohesion_weight", "oops");
    QVERIFY(sweep.count_label()->text().contains("not a number"));
    sweep.set_axis(1, "(no parameter)", "");
    QVERIFY(p->add_sweep(sweep).empty());
    QCOMPARE(p->model()->rowCount(), 14);

    // Paired seeds: every behavior of a repeat and swarm size meets the same world.
    std::map<std::pair<std::size_t, std::size_t>, std::set<std::uint64_t>> seeds;
    for (int i = 2; i < 14; ++i) seeds[{p->model()->test(i).groups[0].drones, p->model()->test(i).repeat}].insert(p->model()->test(i).seed);
    QCOMPARE(seeds.size(), std::size_t{4});
    for (const auto& [key, s] : seeds) QCOMPARE(s.size(), std::size_t{1});

    // Reorder and remove.
    const std::string first = p->model()->test(0).name, third = p->model()->test(2).name;
    QVERIFY(p->model()->move(0, 1));
    QVERIFY(p->model()->move(1, 1));
    QCOMPARE(p->model()->test(1).name, third);
    QCOMPARE(p->model()->test(2).name, first);
    QVERIFY(p->model()->removeRow(5));
    QCOMPARE(p->model()->rowCount(), 13);

    // Saved: salsa run accepts it, and it expands to exactly these tests, in this order.
    const QString file = dir_.filePath("queue.json");
    QVERIFY(p->save(file).empty());
    const auto expected = rows(*p->model(), *host_);
    QCOMPARE(resolved(load_queue(file.toStdString(), *host_, {}).tests, *host_), expected);
    const CliResult validate = run_salsa({"validate", file});
    QVERIFY2(validate.exit_code == 0 && validate.out.contains("ok (13 tests)"), describe(validate));
    const CliResult expand = run_salsa({"queue", "expand", file});
    QVERIFY2(expand.exit_code == 0 && expand.out.startsWith("13 tests"), describe(expand));
    // Loaded again: the same rows.
    auto again = page();
    QVERIFY(again->open(file).empty());
    QCOMPARE(rows(*again->model(), *host_), expected);
  }

  void edits_are_checked_like_a_test_file() {
    auto p = page();
    QVERIFY(p->add_from_sandbox().empty());
    QVERIFY(p->add_from_sandbox().empty());
    QueueModel& m = *p->model();
    QVERIFY(!m.setData(m.index(0, QueueModel::col_drones), 0));
    QVERIFY2(QString::fromStdString(m.last_error()).contains("drones"), m.last_error().c_str());
    QCOMPARE(m.test(0).groups[0].drones, std::size_t{4});
    QVERIFY(!m.setData(m.index(1, QueueModel::col_name), "sandbox"));  // taken by row 1
    QVERIFY(QString::fromStdString(m.last_error()).contains("taken"));
    QVERIFY(m.setData(m.index(0, QueueModel::col_drones), 12));
    QCOMPARE(m.test(0).groups[0].drones, std::size_t{12});
    QVERIFY(m.setData(m.index(0, QueueModel::col_time), 2.5));
    QCOMPARE(m.test(0).time, 2.5);
    // A whole test as JSON.
    auto j = nlohmann::json::parse(m.test_json(1));
    j["behavior"]["name"] = "flocking";
    j["behavior"].erase("params");
    QVERIFY(m.replace(1, j.dump()).empty());
    QCOMPARE(m.test(1).groups[0].behavior.name, std::string("flocking"));
    j["behavior"]["name"] = "no_such_behavior";
    QVERIFY(!m.replace(1, j.dump()).empty());
    QCOMPARE(m.test(1).groups[0].behavior.name, std::string("flocking"));
  }

  void a_bad_queue_file_keeps_the_queue() {
    auto p = page();
    QVERIFY(p->add_from_sandbox().empty());
    const auto before = rows(*p->model(), *host_);
    const QString bad = dir_.filePath("bad.json");
    QVERIFY(write_file(bad, R"({"tests": [{"behavior": "random_walk", "drones": 0}]})"));
    const std::string why = p->open(bad);
    QVERIFY2(QString::fromStdString(why).startsWith(bad + ": tests[0]"), why.c_str());
    QVERIFY(QString::fromStdString(why).contains("drones"));
    QVERIFY(!QString::fromStdString(why).contains('\n'));
    QCOMPARE(rows(*p->model(), *host_), before);
    // Saving a queue salsa run would refuse leaves the file there as it was.
    const QString kept = dir_.filePath("kept.json");
    QVERIFY(write_file(kept, "precious"));
    auto twice = page();
    QVERIFY(twice->add_from_sandbox().empty());
    QVERIFY(twice->add_from_sandbox().empty());  // same world, seed and behavior: the same test twice
    QVERIFY(!twice->save(kept).empty());
    QCOMPARE(read_file(kept), QByteArray("precious"));
  }

  void a_queue_run_from_the_gui_writes_what_salsa_run_writes() {
    auto p = page();
    QVERIFY(p->add_from_sandbox().empty());
    SweepDialog sweep(host_, parse_test(sandbox_test, "sandbox", *host_));
    sweep.drones()->setText("2, 3");
    QVERIFY(p->add_sweep(sweep).empty());  // random_walk × 2 sizes
    QCOMPARE(p->model()->rowCount(), 3);
    const QString gui_out = dir_.filePath("gui-run");
    QVERIFY(p->run(gui_out, {"--no-plots"}).empty());
    QVERIFY2(p->wait(300000), qPrintable(p->log_text()));
    for (int i = 0; i < 3; ++i) QCOMPARE(p->model()->status(i), QueueModel::Status::done);
    QVERIFY(p->last_message().contains("queue finished"));
    // The result column: each finished test's found targets, as its outcome.csv has them.
    QCOMPARE(p->model()->headerData(QueueModel::col_result, Qt::Horizontal).toString(), QString("result"));
    for (int i = 0; i < 3; ++i) {
      const QString result = p->model()->data(p->model()->index(i, QueueModel::col_result)).toString();
      const QStringList outcome = QString::fromUtf8(read_file(gui_out + "/" + QString::fromStdString(p->model()->test(i).name) + "/outcome.csv")).trimmed().split(QChar(10));
      const QStringList names = outcome[0].split(','), values = outcome[1].split(',');
      const QString found = values[static_cast<int>(names.indexOf("targets_found"))], total = values[static_cast<int>(names.indexOf("targets"))];
      QVERIFY2(result.startsWith(QString("found %1 / %2 (").arg(found, total)), qPrintable(result));
    }
    // The same saved file, run by the CLI.
    const QString cli_out = dir_.filePath("cli-run");
    const CliResult r = run_salsa({"run", gui_out + ".queue.json", "--out", cli_out, "--no-plots", "-q"});
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto a = results_snapshot(gui_out), b = results_snapshot(cli_out);
    QVERIFY(a.size() > 10);
    QCOMPARE(a.keys(), b.keys());
    for (const QString& k : a.keys()) QVERIFY2(a[k] == b[k], qPrintable(k));
    // Run again into the same folder: it resumes (nothing is left to do) and changes nothing.
    QVERIFY(p->run(gui_out, {"--no-plots"}).empty());
    QVERIFY2(p->wait(300000), qPrintable(p->log_text()));
    QVERIFY(p->log_text().contains("--resume"));
    for (int i = 0; i < 3; ++i) QCOMPARE(p->model()->status(i), QueueModel::Status::done);
    QCOMPARE(results_snapshot(gui_out), a);
  }

  // Run…'s folder dialog takes an existing folder, clicked (a stopped run's, to resume it), a new one
  // typed, and goes into a folder typed with a trailing slash.
  void the_run_dialog_takes_an_existing_folder() {
    QVERIFY(QDir().mkpath(dir_.filePath("runs/stopped")));
    auto answer = [&](const std::function<void(QFileDialog*)>& act) {
      QTimer::singleShot(300, [act] {
        for (QWidget* w : QApplication::topLevelWidgets())
          if (auto* d = qobject_cast<QFileDialog*>(w); d && d->isVisible()) act(d);
      });
      QTimer::singleShot(3000, [] {  // still open: the pick did not take
        for (QWidget* w : QApplication::topLevelWidgets())
          if (auto* d = qobject_cast<QFileDialog*>(w); d && d->isVisible()) d->reject();
      });
      return ask_save_file(nullptr, "Output folder", dir_.filePath("runs/new"), {}, {}, true);
    };
    const QString existing = answer([&](QFileDialog* d) {
      d->setDirectory(dir_.filePath("runs"));
      auto* list = d->findChild<QAbstractItemView*>("listView");
      if (!list->isVisible()) list = d->findChild<QAbstractItemView*>("treeView");  // the detail view
      QTRY_VERIFY(list->model()->rowCount(list->rootIndex()) > 0);
      const QModelIndex item = list->model()->index(0, 0, list->rootIndex());
      QCOMPARE(item.data().toString(), QString("stopped"));
      QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, list->visualRect(item).center());  // a click on it
      QCOMPARE(d->findChild<QLineEdit*>("fileNameEdit")->text(), QString("stopped"));
      static_cast<QDialog*>(d)->accept();
    });
    QCOMPARE(QFileInfo(existing).canonicalFilePath(), QFileInfo(dir_.filePath("runs/stopped")).canonicalFilePath());
    const QString typed = answer([&](QFileDialog* d) {
      d->setDirectory(dir_.filePath("runs"));
      d->findChild<QLineEdit*>("fileNameEdit")->setText("fresh");
      static_cast<QDialog*>(d)->accept();
    });
    QCOMPARE(QFileInfo(typed).fileName(), QString("fresh"));
    QVERIFY(!QFileInfo::exists(typed));  // made by the run, not the dialog
    QString went;
    const QString navigated = answer([&](QFileDialog* d) {
      d->findChild<QLineEdit*>("fileNameEdit")->setText(dir_.filePath("runs") + "/");
      static_cast<QDialog*>(d)->accept();  // goes there, stays open
      went = d->directory().absolutePath();
      d->findChild<QLineEdit*>("fileNameEdit")->setText("stopped");
      static_cast<QDialog*>(d)->accept();
    });
    QCOMPARE(went, QDir(dir_.filePath("runs")).absolutePath());
    QCOMPARE(QFileInfo(navigated).fileName(), QString("stopped"));
  }

  // The progress counts this queue's tests before any run; a run's plots open from OUT/<test>/plots;
  // the queue reopened shows its finished rows as done; another queue is refused that folder.
  void progress_plots_reopen_and_another_queues_folder() {
    auto p = page();
    QCOMPARE(p->progress()->text(), QString("no tests"));
    QVERIFY(p->add_from_sandbox().empty());
    SweepDialog sweep(host_, parse_test(sandbox_test, "sandbox", *host_));
    sweep.drones()->setText("2, 3");
    QVERIFY(p->add_sweep(sweep).empty());
    QCOMPARE(p->progress()->maximum(), 3);
    QCOMPARE(p->progress()->text(), QString("0 / 3 tests"));  // not "0 / 100"
    const QString out = dir_.filePath("plotted");
    QVERIFY(p->run(out).empty());
    QVERIFY2(p->wait(300000), qPrintable(p->log_text()));
    QCOMPARE(p->progress()->text(), QString("3 / 3 tests"));
    QString opened;
    QStringList pngs;
    p->set_plots_opener([&](const QString& folder, const QStringList& files) { opened = folder, pngs = files; });
    p->show_plots(1);
    QCOMPARE(opened, out + "/" + q(p->model()->test(1).name) + "/plots");
    QVERIFY2(!pngs.isEmpty(), qPrintable(p->last_message()));
    for (const QString& f : pngs) QVERIFY2(QFileInfo(opened + "/" + f).size() > 1000, qPrintable(f));

    // Reopened in a new window: the rows already in OUT are done, the progress says so.
    auto again = page();
    QVERIFY(again->open(out + ".queue.json").empty());
    for (int i = 0; i < 3; ++i) QCOMPARE(again->model()->status(i), QueueModel::Status::done);
    QCOMPARE(again->progress()->text(), QString("3 / 3 tests"));
    QVERIFY2(again->last_message().contains("3 already done"), qPrintable(again->last_message()));
    QCOMPARE(again->output_dir(), out);

    // Another queue into that folder: refused as salsa run refuses it, nothing started, nothing changed.
    const auto before = results_snapshot(out);
    auto other = page();
    QVERIFY(other->add_from_sandbox().empty());
    other->model()->setData(other->model()->index(0, QueueModel::col_seed), 77);
    const std::string why = other->run(out);
    QVERIFY2(why.find("queue.json: holds the results of another queue") != std::string::npos, why.c_str());
    QVERIFY(!other->running());
    QVERIFY(!other->log_text().contains("--resume"));
    QCOMPARE(results_snapshot(out), before);
    // The CLI says the same of that queue.
    QVERIFY(other->save(dir_.filePath("other.json")).empty());
    const CliResult r = run_salsa({"run", dir_.filePath("other.json"), "--out", out, "-q"});
    QVERIFY2(r.exit_code != 0 && r.err.contains("holds the results of another queue"), describe(r));
  }

  // salsa-gui --yes: a queue over 10,000 tests opens, and its run passes --yes to salsa run.
  void yes_allows_large_queues() {
    const QString file = dir_.filePath("large.json");
    QVERIFY(write_file(file, R"({"repeats": 10001, "tests": [{"name": "big", "behavior": "random_walk", "drones": 2, "time": 1,
      "map": {"name": "empty", "params": {"size": 100}}, "targets": {"kind": "tree", "count": 1}}]})"));
    auto p = page();
    const std::string why = p->open(file);
    QVERIFY2(why.find("--yes") != std::string::npos, why.c_str());
    p->set_allow_large(true);
    QVERIFY(p->open(file).empty());
    QCOMPARE(p->model()->rowCount(), 10001);
    p->set_salsa_program("/bin/true");  // the command line is what is checked, not a 10,001-test run
    QVERIFY(p->run(dir_.filePath("large-out")).empty());
    QVERIFY(p->wait(60000));
    QVERIFY2(p->log_text().contains(" --yes"), qPrintable(p->log_text().left(300)));
  }

  void load_into_sandbox_and_mode_switches_keep_state() {
    MainWindow w(*host_);
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    for (int i = 0; i < 30; ++i) w.sandbox()->step();
    w.sandbox()->engine().sync();
    const double t = w.sandbox()->engine().snapshot()->time;
    QVERIFY(t > 0);
    QVERIFY(w.queue_page()->add_from_sandbox().empty());
    w.set_mode(MainWindow::Mode::queue);
    QVERIFY(!w.sandbox()->view()->isVisible());
    QVERIFY(w.queue_page()->isVisible());
    QVERIFY(w.queue_page()->open(q(source_dir() / "examples/sweep-queue.json")).empty());
    w.set_mode(MainWindow::Mode::map_creator);
    MapEditor& editor = *w.map_editor();
    QVERIFY(editor.isVisible());
    editor.set_tool(MapEditor::Tool::line);
    QTest::mousePress(editor.canvas(), Qt::LeftButton, Qt::NoModifier, editor.to_px({20, 20}));
    QTest::mouseMove(editor.canvas(), editor.to_px({60, 20}));
    QTest::mouseRelease(editor.canvas(), Qt::LeftButton, Qt::NoModifier, editor.to_px({60, 20}));
    QCOMPARE(editor.map().lines.size(), std::size_t{1});
    w.set_mode(MainWindow::Mode::sandbox);
    QVERIFY(w.sandbox()->view()->isVisible());
    QCOMPARE(w.sandbox()->engine().snapshot()->time, t);  // the sandbox kept its run
    w.set_mode(MainWindow::Mode::queue);
    QCOMPARE(w.queue_page()->model()->rowCount(), 12);  // the queue kept its rows
    w.set_mode(MainWindow::Mode::map_creator);
    QCOMPARE(editor.map().lines.size(), std::size_t{1});  // the map creator kept its drawing
    QVERIFY(editor.undo_stack()->canUndo());
    // "Save and use in sandbox": the sandbox flies in the drawn map at once.
    QTemporaryDir dir;
    const QString map_file = dir.filePath("drawn.json");
    QVERIFY(editor.save(map_file).empty());
    QPushButton* use = nullptr;
    for (auto* b : editor.findChildren<QPushButton*>())
      if (b->text().contains("use in sandbox")) use = b;
    QVERIFY(use);
    use->click();
    QCOMPARE(w.mode(), MainWindow::Mode::sandbox);
    QCOMPARE(q(w.sandbox()->engine().current_test()->map_file), map_file);
    w.set_mode(MainWindow::Mode::queue);
    QCOMPARE(w.queue_page()->model()->rowCount(), 12);
    // A queue row into the sandbox: its start state, in sandbox mode.
    w.queue_page()->table()->selectRow(4);
    const TestSpec row = w.queue_page()->model()->test(4);
    QPushButton* load = nullptr;
    for (auto* b : w.queue_page()->findChildren<QPushButton*>())
      if (b->text() == "Load into sandbox") load = b;
    QVERIFY(load);
    load->click();
    QCOMPARE(w.mode(), MainWindow::Mode::sandbox);
    const auto current = w.sandbox()->engine().current_test();
    QVERIFY(current);
    QCOMPARE(resolved_json(*current, *host_), resolved_json(row, *host_));
    QCOMPARE(w.sandbox()->engine().snapshot()->time, 0.0);
  }
};

QTEST_MAIN(GuiQueue)
#include "gui_queue.moc"
