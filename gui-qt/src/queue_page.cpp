// Queue mode: the table of tests, its buttons and a run of the queue (the sweep dialog: sweep_dialog.cpp).
#include "queue_page.hpp"

#include <nlohmann/json.hpp>

#include <QCheckBox>
#include <QCoreApplication>
#include <QDateTime>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QListWidget>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include "number_field.hpp"
#include <QSplitter>
#include <QTableView>
#include <QThread>
#include <QPixmap>
#include <QDropEvent>
#include <QVBoxLayout>

#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/results/queue_summary.hpp"
#include "salsa_process.hpp"
#include "save_checked.hpp"

namespace salsa::gui {

using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

QString q(const std::string& s) { return QString::fromStdString(s); }

/// A new-style dialog around `content`, OK / Cancel.
QDialog* dialog_around(QWidget* content, QWidget* parent, const QString& title) {
  auto* d = new QDialog(parent);
  d->setWindowTitle(title);
  auto* layout = new QVBoxLayout(d);
  layout->addWidget(content);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, d);
  QObject::connect(buttons, &QDialogButtonBox::accepted, d, &QDialog::accept);
  QObject::connect(buttons, &QDialogButtonBox::rejected, d, &QDialog::reject);
  layout->addWidget(buttons);
  return d;
}

/// Rows dragged within the table are moved by the model (moveRows), not copied and removed.
class QueueTable : public QTableView {
 protected:
  void dropEvent(QDropEvent* event) override {
    auto* m = qobject_cast<QueueModel*>(model());
    if (event->source() != this || !m) return QTableView::dropEvent(event);
    const QModelIndex at = indexAt(event->position().toPoint());
    int to = at.isValid() ? at.row() : m->rowCount();
    if (at.isValid() && event->position().y() > visualRect(at).center().y()) ++to;  // the lower half: after it
    std::vector<bool> picked(static_cast<std::size_t>(m->rowCount()), false);
    for (const auto& i : selectionModel()->selectedRows()) picked[static_cast<std::size_t>(i.row())] = true;
    // The order wanted: unpicked rows before the drop point, the picked rows, the rest.
    std::vector<int> order, current;
    for (int i = 0; i < m->rowCount(); ++i) current.push_back(i);
    for (int i = 0; i < to; ++i) if (!picked[static_cast<std::size_t>(i)]) order.push_back(i);
    for (int i = 0; i < m->rowCount(); ++i) if (picked[static_cast<std::size_t>(i)]) order.push_back(i);
    for (int i = to; i < m->rowCount(); ++i) if (!picked[static_cast<std::size_t>(i)]) order.push_back(i);
    // Filled from the top, so every move is upwards.
    for (int pos = 0; pos < static_cast<int>(order.size()); ++pos) {
      const int at_now = static_cast<int>(std::find(current.begin(), current.end(), order[static_cast<std::size_t>(pos)]) - current.begin());
      if (at_now == pos) continue;
      m->moveRows({}, at_now, 1, {}, pos);
      current.erase(current.begin() + at_now);
      current.insert(current.begin() + pos, order[static_cast<std::size_t>(pos)]);
    }
    event->setDropAction(Qt::CopyAction);  // the view must not remove the source rows
    event->accept();
  }
};

}  // namespace

// ---------------------------------------------------------------- the page

QueuePage::QueuePage(std::shared_ptr<const PluginHost> host, std::vector<fs::path> plugin_dirs, QWidget* parent)
    : QWidget(parent), host_(std::move(host)), plugin_dirs_(std::move(plugin_dirs)) {
  model_ = new QueueModel(host_, this);
  auto* layout = new QVBoxLayout(this);

  auto* edit_row = new QHBoxLayout;
  auto button = [&](const char* text, const char* tip, auto&& fn) {
    auto* b = new QPushButton(text);
    b->setToolTip(tip);
    connect(b, &QPushButton::clicked, this, fn);
    edit_row->addWidget(b);
    return b;
  };
  button("Add from sandbox", "the sandbox's test as it is set now (behavior, parameters, map, drones, seed)", [this] { add_from_sandbox(); });
  button("Add sweep…", "behaviors × parameter values × swarm sizes × repeats, on the sandbox's world", [this] {
    std::string why;
    const auto base = sandbox_ ? sandbox_(&why) : std::nullopt;
    if (!base) return show_message(q("no sandbox test to sweep over: " + why));
    auto* sweep = new SweepDialog(host_, *base, nullptr, model_->options());
    QDialog* d = dialog_around(sweep, this, "Add a sweep");
    if (d->exec() == QDialog::Accepted) add_sweep(*sweep);
    d->deleteLater();
  });
  button("Edit…", "the selected test as JSON (cells: double-click to edit name, drones, targets, time, seed)", [this] { edit_json(selected_row()); });
  button("Remove", "remove the selected tests", [this] {
    auto rows = table_->selectionModel()->selectedRows();
    std::sort(rows.begin(), rows.end(), [](auto& a, auto& b) { return a.row() > b.row(); });
    for (const auto& r : rows) model_->removeRow(r.row());
  });
  button("Up", "move the selected test earlier", [this] {
    const int r = selected_row();
    if (model_->move(r, -1)) table_->selectRow(r - 1);
  });
  button("Down", "move the selected test later", [this] {
    const int r = selected_row();
    if (model_->move(r, +1)) table_->selectRow(r + 1);
  });
  edit_row->addStretch();
  button("Open…", "load a queue or test file (sweeps and repeats are expanded)", [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Open a queue", {}, "Queues and tests (*.json)");
    if (!f.isEmpty()) open(f);
  });
  button("Save…", "save the queue: the file `salsa run` reads", [this] {
    if (model_->rowCount() == 0) return show_message("the queue holds no tests: add one before saving");  // before a name is asked for
    const QString f = ask_save_file(this, "Save the queue", "queue.json", "Queues (*.json)");
    if (!f.isEmpty()) save(f);
  });
  layout->addLayout(edit_row);

  table_ = new QueueTable;
  table_->setModel(model_);
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  table_->setDragDropMode(QAbstractItemView::InternalMove);
  table_->setDragEnabled(true);
  table_->setDropIndicatorShown(true);
  table_->setDragDropOverwriteMode(false);
  table_->setDefaultDropAction(Qt::MoveAction);
  table_->horizontalHeader()->setSectionResizeMode(QHeaderView::Interactive);
  table_->horizontalHeader()->setStretchLastSection(true);
  table_->setAlternatingRowColors(true);
  connect(model_, &QAbstractItemModel::rowsInserted, table_, [this] { table_->resizeColumnsToContents(); });
  connect(model_, &QAbstractItemModel::modelReset, table_, [this] { table_->resizeColumnsToContents(); });
  // The progress counts this queue's tests, whatever it holds, from before any run.
  for (auto sig : {&QAbstractItemModel::rowsInserted, &QAbstractItemModel::rowsRemoved})
    connect(model_, sig, this, [this] { update_progress(-1); });
  connect(model_, &QAbstractItemModel::modelReset, this, [this] { update_progress(-1); });
  connect(model_, &QueueModel::edit_refused, this, [this](const QString& why) { show_message(why); });
  connect(table_, &QTableView::doubleClicked, this, [this](const QModelIndex& i) {
    if (!(model_->flags(i) & Qt::ItemIsEditable) && model_->status(i.row()) == QueueModel::Status::done) show_plots(i.row());
  });

  auto* run_row = new QHBoxLayout;
  run_button_ = new QPushButton("Run…");
  run_button_->setToolTip("save the queue beside an output folder and run it there with salsa run, in the background");
  stop_button_ = new QPushButton("Stop");
  stop_button_->setEnabled(false);
  jobs_ = new NumberField({"jobs", 1, 1, 256, "", "", 1});
  jobs_->setValue(std::max(1, QThread::idealThreadCount()));
  jobs_->setToolTip("tests run at once (allowed: whole number in [1, 256])");
  plots_ = new QCheckBox("plots");
  plots_->setChecked(true);
  auto* plots_button = new QPushButton("Plots");
  plots_button->setToolTip("the selected finished test's plots");
  auto* sandbox_button = new QPushButton("Load into sandbox");
  run_row->addWidget(run_button_);
  run_row->addWidget(stop_button_);
  run_row->addWidget(new QLabel("jobs"));
  run_row->addWidget(jobs_);
  run_row->addWidget(plots_);
  progress_ = new QProgressBar;
  update_progress(0);
  run_row->addWidget(progress_, 1);
  run_row->addWidget(plots_button);
  run_row->addWidget(sandbox_button);
  layout->addWidget(table_, 1);
  layout->addLayout(run_row);
  state_ = new QLabel("Add tests from the sandbox or a sweep, or open a queue file.");
  state_->setWordWrap(true);
  layout->addWidget(state_);
  log_ = new QPlainTextEdit;
  log_->setReadOnly(true);
  log_->setMaximumBlockCount(2000);
  log_->setMaximumHeight(140);
  log_->setPlaceholderText("salsa run's output");
  layout->addWidget(log_);

  connect(run_button_, &QPushButton::clicked, this, [this] {
    if (model_->rowCount() == 0) return show_message("the queue holds no tests: add one before running");  // before a folder is asked for
    const QString base = QDir::homePath() + "/salsa-results/queue-" + QDateTime::currentDateTime().toString("yyyyMMdd-HHmmss");
    const QString out = ask_save_file(this, "Output folder for the queue's results", base, {}, {}, true);
    if (!out.isEmpty()) run(out);
  });
  connect(stop_button_, &QPushButton::clicked, this, &QueuePage::stop);
  connect(plots_button, &QPushButton::clicked, this, [this] { show_plots(selected_row()); });
  connect(sandbox_button, &QPushButton::clicked, this, [this] {
    const int r = selected_row();
    if (r >= 0 && load_into_sandbox_) load_into_sandbox_(model_->test(r));
  });
  process_ = new SalsaProcess(log_, this);
  connect(process_, &SalsaProcess::printed, this, &QueuePage::update_statuses);
  connect(process_, &SalsaProcess::poll, this, &QueuePage::update_statuses);
  connect(process_, &SalsaProcess::finished, this, [this](int code, bool crashed) {
    update_statuses();
    run_button_->setEnabled(true);
    stop_button_->setEnabled(false);
    show_message(crashed      ? "salsa run crashed; run again to resume the rest"
                 : code == 0 ? "queue finished: results in " + out_
                             : QString("salsa run ended with status %1 (see the log; failed tests show why in the table)").arg(code),
                 false);
  });
  connect(process_, &SalsaProcess::failed_to_start, this, [this](const QString& why) {
    run_button_->setEnabled(true);
    stop_button_->setEnabled(false);
    show_message(why);
  });
}

QueuePage::~QueuePage() { delete process_; }  // stops a run while the page it reports to is whole

void QueuePage::set_host(std::shared_ptr<const PluginHost> host) {
  host_ = host;
  model_->set_host(std::move(host));
}

int QueuePage::selected_row() const {
  const auto rows = table_->selectionModel()->selectedRows();
  return rows.isEmpty() ? (table_->currentIndex().isValid() ? table_->currentIndex().row() : -1) : rows.front().row();
}

void QueuePage::show_message(const QString& text, bool error) {
  last_message_ = text;
  show_state(state_, this, text, error);
}

std::string QueuePage::add_from_sandbox() {
  std::string why;
  auto test = sandbox_ ? sandbox_(&why) : std::nullopt;
  if (!test) {
    show_message(q("no sandbox test to add: " + why));
    return why.empty() ? "no sandbox" : why;
  }
  test->changes.clear();
  model_->add({std::move(*test)});
  show_message(QString("%1 tests in the queue").arg(model_->rowCount()), false);
  return {};
}

std::string QueuePage::add_sweep(const SweepDialog& sweep) {
  std::string why;
  auto tests = sweep.expand(&why);
  if (!tests) {
    show_message(q(why));
    return why;
  }
  const auto n = tests->size();
  model_->add(std::move(*tests));
  show_message(QString("added %1 tests; %2 in the queue").arg(n).arg(model_->rowCount()), false);
  return {};
}

std::string QueuePage::open(const QString& file) {
  const std::string why = model_->load(file.toStdString());
  if (!why.empty()) return show_message(q(why)), why;
  QString message = QString("%1: %2 tests").arg(file).arg(model_->rowCount());
  // Run saves the queue as <out>.queue.json: reopened, it shows what <out> already holds.
  if (!running() && file.endsWith(".queue.json")) {
    const QString dir = QFileInfo(file.chopped(int(std::string_view(".queue.json").size()))).absoluteFilePath();
    if (QFileInfo(dir).isDir()) {
      out_ = dir;
      run_names_.clear();
      for (int i = 0; i < model_->rowCount(); ++i) run_names_.insert(model_->test(i).name);
      update_statuses();
      int done = 0;
      for (int i = 0; i < model_->rowCount(); ++i) done += model_->status(i) == QueueModel::Status::done;
      message += QString("; %1 already done in %2 (Run into it resumes the rest)").arg(done).arg(dir);
    }
  }
  show_message(message, false);
  return {};
}

std::string QueuePage::save(const QString& file) {
  const std::string why = model_->save(file.toStdString());
  show_message(why.empty() ? QString("saved %1 (salsa run %1 runs it)").arg(file) : q(why), !why.empty());
  return why;
}

void QueuePage::edit_json(int row) {
  if (row < 0 || row >= model_->rowCount()) return;
  auto* text = new QPlainTextEdit(q(model_->test_json(row)));
  text->setMinimumSize(560, 480);
  QDialog* d = dialog_around(text, this, QString("Edit test %1").arg(row + 1));
  while (d->exec() == QDialog::Accepted) {
    const std::string why = model_->replace(row, text->toPlainText().toStdString());
    if (why.empty()) break;
    QMessageBox::warning(d, "salsa", q(why));  // the dialog stays open with the text as typed
  }
  d->deleteLater();
}

std::string QueuePage::run(const QString& out, const QStringList& extra_args) {
  if (running()) return show_message("a queue is running; stop it first"), "a queue is running";
  const QString dir = QFileInfo(out).absoluteFilePath();
  const QString file = dir + ".queue.json";
  if (model_->rowCount() == 0) return show_message("the queue holds no tests: add one before running"), "the queue holds no tests";
  // As salsa run decides: a folder whose queue.json records this queue resumes; another queue's
  // folder is refused (never taken over with --resume); anything else is salsa run's to judge.
  bool resume = false;
  try {
    std::vector<TestSpec> tests;
    for (int i = 0; i < model_->rowCount(); ++i) tests.push_back(model_->test(i));
    const QueueRecord record = queue_record(tests, *host_, {});
    check_queue_folder(dir.toStdString(), record, false, false);
    resume = QFileInfo::exists(dir + "/queue.json");
  } catch (const std::exception& e) {
    return show_message(q(e.what())), e.what();
  }
  if (const std::string why = model_->save(file.toStdString()); !why.empty()) return show_message(q(why)), why;
  out_ = dir;
  run_names_.clear();
  for (int i = 0; i < model_->rowCount(); ++i) run_names_.insert(model_->test(i).name);
  model_->clear_statuses();
  update_progress(0);
  QStringList args{"run", file, "--out", dir, "--jobs", QString::number(jobs_->whole())};
  if (!plots_->isChecked()) args << "--no-plots";
  if (resume) args << "--resume";  // its finished tests are kept only where they are the tests asked for now
  if (model_->options().yes && static_cast<std::size_t>(model_->rowCount()) > model_->options().max_tests) args << "--yes";
  for (const auto& d : plugin_dirs_) args << "--plugin-dir" << q(d.string());
  args << extra_args;
  process_->start(args);
  run_button_->setEnabled(false);
  stop_button_->setEnabled(true);
  show_message("running " + QString::number(model_->rowCount()) + " tests into " + dir, false);
  return {};
}

void QueuePage::set_salsa_program(QString program) { process_->set_program(std::move(program)); }

void QueuePage::stop() { process_->stop(); }

bool QueuePage::running() const { return process_->running(); }

bool QueuePage::wait(int ms) { return process_->wait(ms); }

QString QueuePage::log_text() const { return log_->toPlainText(); }

std::string QueuePage::outcome_words(const QString& folder) {
  // outcome.csv: a header and one row (docs/output-format.md); its found targets, and coverage if measured.
  QFile file(folder + "/outcome.csv");
  if (!file.open(QIODevice::ReadOnly)) return {};
  const QStringList lines = QString::fromUtf8(file.readAll()).split('\n', Qt::SkipEmptyParts);
  if (lines.size() < 2) return {};
  const QStringList names = lines[0].trimmed().split(','), values = lines[1].trimmed().split(',');
  auto value = [&](const char* name) { return values.value(static_cast<int>(names.indexOf(name))); };
  QStringList words;
  if (const QString total = value("targets"); !total.isEmpty() && total != "0")
    words << QString("found %1 / %2 (%3 %)").arg(value("targets_found"), total).arg(100 * value("fraction_found").toDouble(), 0, 'f', 1);
  if (const QString coverage = value("coverage"); !coverage.isEmpty())
    words << QString("coverage %1 %").arg(100 * coverage.toDouble(), 0, 'f', 1);
  return words.join(", ").toStdString();
}

void QueuePage::update_statuses() {
  if (out_.isEmpty()) return;
  int finished = 0;
  for (int row = 0; row < model_->rowCount(); ++row) {
    const std::string name = model_->test(row).name;
    if (!run_names_.contains(name)) continue;  // added since
    const QString done = out_ + "/" + q(name), partial = out_ + "/." + q(name) + ".partial";
    if (QFileInfo::exists(done + "/config.json")) {
      model_->set_status(row, QueueModel::Status::done, {}, outcome_words(done));
      ++finished;
    } else if (QFile error(partial + "/error.txt"); error.open(QIODevice::ReadOnly)) {
      model_->set_status(row, QueueModel::Status::failed, QString::fromUtf8(error.readAll()).trimmed().toStdString());
      ++finished;
    } else if (QFileInfo::exists(partial)) {
      model_->set_status(row, running() ? QueueModel::Status::running : QueueModel::Status::failed,
                         running() ? "" : "interrupted (Run into the same folder resumes it)");
      finished += running() ? 0 : 1;
    }
  }
  update_progress(finished);
}

void QueuePage::update_progress(int finished) {
  const int n = model_->rowCount();
  if (finished < 0) {  // counted from the table: rows done or failed
    finished = 0;
    for (int i = 0; i < n; ++i) finished += model_->status(i) == QueueModel::Status::done || model_->status(i) == QueueModel::Status::failed;
  }
  if (n == 0) {  // a range of 0..0 would show a busy bar
    progress_->setRange(0, 1);
    progress_->setValue(0);
    progress_->setFormat("no tests");
    return;
  }
  progress_->setRange(0, n);
  progress_->setValue(std::min(finished, n));
  progress_->setFormat("%v / %m tests");
}

void QueuePage::show_plots(int row) {
  if (row < 0 || row >= model_->rowCount()) return;
  // salsa run writes a test's PNGs into OUT/<test>/plots/.
  const QString folder = out_.isEmpty() ? QString() : out_ + "/" + q(model_->test(row).name) + "/plots";
  const QStringList pngs = folder.isEmpty() ? QStringList() : QDir(folder).entryList({"*.png"}, QDir::Files, QDir::Name);
  if (pngs.isEmpty())
    return show_message(folder.isEmpty() ? "no plots yet for this test: run the queue (with plots) first"
                                         : "no plots in " + folder + ": run the queue with \"plots\" checked");
  if (open_plots_) return open_plots_(folder, pngs);
  const QDir dir(folder);
  auto* d = new QDialog(this);
  d->setAttribute(Qt::WA_DeleteOnClose);
  d->setWindowTitle("Plots of " + q(model_->test(row).name) + " (" + folder + ")");
  d->resize(1100, 760);
  auto* split = new QSplitter(d);
  auto* list = new QListWidget;
  list->addItems(pngs);
  list->setMaximumWidth(260);
  auto* image = new QLabel;
  image->setAlignment(Qt::AlignCenter);
  auto* scroll = new QScrollArea;
  scroll->setWidget(image);
  scroll->setWidgetResizable(true);
  split->addWidget(list);
  split->addWidget(scroll);
  (new QVBoxLayout(d))->addWidget(split);
  connect(list, &QListWidget::currentTextChanged, d, [image, dir](const QString& f) { image->setPixmap(QPixmap(dir.filePath(f))); });
  list->setCurrentRow(0);
  d->show();
}

}  // namespace salsa::gui
