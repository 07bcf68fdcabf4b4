#include "tune_page.hpp"

#include <nlohmann/json.hpp>

#include <QChart>
#include <QChartView>
#include <QCheckBox>
#include <QComboBox>
#include <QCoreApplication>
#include <QDateTime>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QLineSeries>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QScatterSeries>
#include "number_field.hpp"
#include <QSplitter>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QThread>
#include <QValueAxis>
#include <QVBoxLayout>
#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>

#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa_process.hpp"
#include "save_checked.hpp"

namespace salsa::gui {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

namespace {

QString q(const std::string& s) { return QString::fromStdString(s); }

enum Column { col_key, col_value, col_min, col_max, col_log, col_allowed, col_count };

std::string text_of(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Reads a tune file the way `salsa tune` does, from text: its spec, or why it is refused (the
/// temporary file's name replaced by "tune").
std::optional<TuneSpec> check_tune(const std::string& text, const PluginHost& host, std::string* why) {
  QTemporaryDir dir;
  const fs::path file = fs::path(dir.path().toStdString()) / "tune.json";
  std::ofstream(file) << text;
  try {
    return load_tune(file, host);
  } catch (const std::exception& e) {
    *why = e.what();
    if (auto at = why->find(file.string()); at != std::string::npos) why->replace(at, file.string().size(), "tune");
    return std::nullopt;
  }
}

}  // namespace

TunePage::TunePage(std::shared_ptr<const PluginHost> host, std::vector<fs::path> plugin_dirs, QWidget* parent)
    : QWidget(parent), host_(std::move(host)), plugin_dirs_(std::move(plugin_dirs)) {
  build();
  process_ = new SalsaProcess(log_, this);
  connect(process_, &SalsaProcess::poll, this, &TunePage::update_chart);
  connect(process_, &SalsaProcess::finished, this, [this](int code, bool crashed) {
    update_chart();
    run_button_->setEnabled(true);
    stop_button_->setEnabled(false);
    load_best_button_->setEnabled(QFileInfo::exists(out_ + "/best.json"));
    if (!crashed && code == 0)
      return show_message("tune finished: the report is " + out_ + "/report.txt (Load best puts the winner in the sandbox)", false);
    show_message(crashed      ? "salsa tune stopped; Run into the same folder resumes it exactly"
                 : code == 2 ? process_->last_line()  // a refusal: salsa tune's one line
                             : QString("salsa tune ended with status %1: %2 (Run into the same folder resumes it)").arg(code).arg(process_->last_line()),
                 !crashed && code == 2);
  });
  connect(process_, &SalsaProcess::failed_to_start, this, [this](const QString& why) {
    run_button_->setEnabled(true);
    stop_button_->setEnabled(false);
    show_message(why);
  });
}

TunePage::~TunePage() { delete process_; }  // stops a run while the page it reports to is whole

void TunePage::set_salsa_program(QString program) { process_->set_program(std::move(program)); }

void TunePage::build() {
  auto* layout = new QHBoxLayout(this);
  auto* split = new QSplitter;
  layout->addWidget(split);

  // ---- Left: what to tune, for what, how.
  auto* left = new QWidget;
  auto* form = new QVBoxLayout(left);
  auto* top = new QHBoxLayout;
  base_label_ = new QLabel("No test yet: set one up in the sandbox, then From sandbox.");
  base_label_->setWordWrap(true);
  auto* take = new QPushButton("From sandbox");
  take->setToolTip("tune the sandbox's test as it is set now (behavior, map, drones, time...)");
  connect(take, &QPushButton::clicked, this, [this] { from_sandbox(); });
  top->addWidget(base_label_, 1);
  top->addWidget(take);
  form->addLayout(top);

  table_ = new QTableWidget(0, col_count);
  table_->setHorizontalHeaderLabels({"tune", "value", "min", "max", "log", "allowed"});
  table_->horizontalHeaderItem(col_key)->setToolTip("tick the numbers to tune");
  table_->horizontalHeaderItem(col_min)->setToolTip("the range searched: type a narrower one inside the allowed range");
  table_->horizontalHeaderItem(col_log)->setToolTip("searched on a log scale (the default for a positive range spanning ×100 or more)");
  table_->verticalHeader()->hide();
  table_->setSelectionMode(QAbstractItemView::SingleSelection);
  table_->horizontalHeader()->setStretchLastSection(true);
  form->addWidget(table_, 1);

  auto* settings = new QFormLayout;
  auto* objective_row = new QHBoxLayout;
  objective_ = new QComboBox;
  objective_->setToolTip("a column of outcome.csv or summary.csv, aggregated over the tuning worlds");
  goal_ = new QComboBox;
  goal_->addItems({"max", "min"});
  aggregate_ = new QComboBox;
  aggregate_->addItems({"mean", "median"});
  objective_row->addWidget(objective_, 1);
  objective_row->addWidget(goal_);
  objective_row->addWidget(aggregate_);
  settings->addRow("Objective", objective_row);
  algorithm_ = new QComboBox;
  for (const std::string& a : tune_algorithms())
    if (a != "nsga2") algorithm_->addItem(q(a));  // one objective here; several: a tune file
  algorithm_->setCurrentText("cmaes");
  algorithm_->setToolTip("cmaes: the default; random, lhs, grid: baselines; bobyqa, neldermead: local from the defaults (docs/tuning.md)");
  settings->addRow("Algorithm", algorithm_);
  auto spin = [](const char* name, double lo, double hi, double value, const std::string& tip) {
    auto* s = new NumberField({name, value, lo, hi, "", tip, 1});
    s->setValue(value);
    s->setToolTip(QString::fromStdString(tip + " (allowed: " + s->spec().range() + ")"));
    return s;
  };
  evaluations_ = spin("budget.evaluations", 1, 1000000, 200, "tests run for tuning, the defaults' included");
  worlds_ = spin("worlds", 1, 100000, 5, "every candidate runs on these paired worlds (seeds)");
  validation_ = spin("validation.worlds", 0, 100000, 10, "held-out worlds the best few and the defaults run on afterwards (0: none)");
  auto* budget_row = new QHBoxLayout;
  budget_row->addWidget(evaluations_);
  budget_row->addWidget(new QLabel("worlds"));
  budget_row->addWidget(worlds_);
  budget_row->addWidget(new QLabel("held out"));
  budget_row->addWidget(validation_);
  settings->addRow("Evaluations", budget_row);
  auto* seed_row = new QHBoxLayout;
  seed_ = new QLineEdit("1");
  seed_->setToolTip(QString("the tune's seed: the worlds and the algorithm's random numbers (whole number in [0, %1])").arg(max_seed));
  racing_ = new QCheckBox("racing");
  racing_->setChecked(true);
  racing_->setToolTip("drop a candidate once it is significantly worse than the best on the worlds seen so far");
  connect(worlds_, &NumberField::valueChanged, racing_, [this](double w) { racing_->setEnabled(w > 1); });
  seed_row->addWidget(seed_, 1);
  seed_row->addWidget(racing_);
  settings->addRow("Seed", seed_row);
  form->addLayout(settings);
  split->addWidget(left);

  // ---- Right: the run and its chart.
  auto* right = new QWidget;
  auto* side = new QVBoxLayout(right);
  auto* chart = new QChart;
  chart->setTitle("Best so far");
  chart->setBackgroundRoundness(0);
  scores_ = new QScatterSeries;
  scores_->setName("candidates");
  scores_->setMarkerSize(6);
  scores_->setColor(QColor(0x9a, 0xb3, 0xd5));
  scores_->setBorderColor(QColor(0x9a, 0xb3, 0xd5));
  best_ = new QLineSeries;
  best_->setName("best so far");
  best_->setPen(QPen(QColor(0x1f, 0x4e, 0x9c), 2));
  defaults_ = new QLineSeries;
  defaults_->setName("defaults");
  defaults_->setPen(QPen(QColor(0x60, 0x60, 0x60), 1.5, Qt::DashLine));
  x_ = new QValueAxis;
  y_ = new QValueAxis;
  x_->setTitleText("evaluations");
  x_->setLabelFormat("%.0f");
  x_->setRange(0, 10);
  y_->setRange(0, 1);
  chart->addAxis(x_, Qt::AlignBottom);
  chart->addAxis(y_, Qt::AlignLeft);
  for (QXYSeries* s : std::initializer_list<QXYSeries*>{scores_, defaults_, best_}) {
    chart->addSeries(s);
    s->attachAxis(x_);
    s->attachAxis(y_);
  }
  chart_view_ = new QChartView(chart);
  chart_view_->setRenderHint(QPainter::Antialiasing);
  chart_view_->setMinimumSize(360, 260);
  side->addWidget(chart_view_, 1);

  auto* run_row = new QHBoxLayout;
  auto* save_button = new QPushButton("Save…");
  save_button->setToolTip("save the tune file: salsa tune FILE runs it");
  connect(save_button, &QPushButton::clicked, this, [this] {
    std::string why;
    if (tune_json(&why).empty()) return show_message(q(why));  // before a name is asked for
    const QString f = ask_save_file(this, "Save the tune file", "tune.json", "Tune files (*.json)");
    if (!f.isEmpty()) save(f);
  });
  run_button_ = new QPushButton("Run…");
  run_button_->setToolTip("save the tune file beside an output folder and run salsa tune into it, in the background");
  connect(run_button_, &QPushButton::clicked, this, [this] {
    std::string why;
    if (tune_json(&why).empty()) return show_message(q(why));  // before a folder is asked for
    const QString base = QDir::homePath() + "/salsa-results/tune-" + QDateTime::currentDateTime().toString("yyyyMMdd-HHmmss");
    const QString out = ask_save_file(this, "Output folder for the tune", base, {}, {}, true);
    if (!out.isEmpty()) run(out);
  });
  stop_button_ = new QPushButton("Stop");
  stop_button_->setEnabled(false);
  connect(stop_button_, &QPushButton::clicked, this, &TunePage::stop);
  jobs_ = new NumberField({"jobs", 1, 1, 256, "", "", 1});
  jobs_->setValue(std::max(1, QThread::idealThreadCount()));
  jobs_->setToolTip("tests run at once (allowed: whole number in [1, 256])");
  auto* open_button = new QPushButton("Open…");
  open_button->setToolTip("show a tune's output folder: its chart, and its winner for Load best");
  connect(open_button, &QPushButton::clicked, this, [this] {
    const QString dir = QFileDialog::getExistingDirectory(this, "A tune's output folder");
    if (!dir.isEmpty()) open_results(dir);
  });
  load_best_button_ = new QPushButton("Load best into sandbox");
  load_best_button_->setEnabled(false);
  load_best_button_->setToolTip("the winner (best.json) on the first tuning world, into the sandbox");
  connect(load_best_button_, &QPushButton::clicked, this, [this] { load_best(); });
  for (QWidget* w : std::initializer_list<QWidget*>{save_button, run_button_, stop_button_, new QLabel("jobs"), jobs_, open_button, load_best_button_})
    run_row->addWidget(w);
  side->addLayout(run_row);
  progress_ = new QProgressBar;
  progress_->setRange(0, 1);
  progress_->setValue(0);
  progress_->setFormat("no tune yet");
  side->addWidget(progress_);
  state_ = new QLabel("Tick the numbers to tune, choose the objective and the budget, then Run.");
  state_->setWordWrap(true);
  side->addWidget(state_);
  log_ = new QPlainTextEdit;
  log_->setReadOnly(true);
  log_->setMaximumBlockCount(2000);
  log_->setMaximumHeight(160);
  log_->setPlaceholderText("salsa tune's output");
  side->addWidget(log_);
  split->addWidget(right);
  split->setStretchFactor(0, 1);
  split->setStretchFactor(1, 1);
}

void TunePage::show_message(const QString& text, bool error) {
  last_message_ = text;
  show_state(state_, this, text, error);
}

// ---------------------------------------------------------------- the tune file

std::string TunePage::from_sandbox() {
  std::string why;
  auto test = sandbox_ ? sandbox_(&why) : std::nullopt;
  if (!test) {
    show_message(q("no sandbox test to tune: " + why));
    return why.empty() ? "no sandbox" : why;
  }
  test->changes.clear();  // the sandbox's live edits: a tune's worlds start from the start state
  try {
    numbers_ = tunable_numbers(*test, *host_);
  } catch (const std::exception& e) {
    show_message(q(e.what()));
    return e.what();
  }
  base_ = std::move(*test);
  const GroupSpec& g = base_->groups.front();
  base_label_->setText(QString("<b>%1</b>: %2, %3 drones%4, map %5, %6 s")
                           .arg(q(base_->name), q(g.behavior.name))
                           .arg(g.drones)
                           .arg(base_->groups.size() > 1 ? QString(" (and %1 more groups)").arg(base_->groups.size() - 1) : QString())
                           .arg(q(base_->map.name))
                           .arg(base_->time));
  table_->setRowCount(0);
  table_->setRowCount(static_cast<int>(numbers_.size()));
  for (std::size_t i = 0; i < numbers_.size(); ++i) {
    const TunableNumber& n = numbers_[i];
    const int r = static_cast<int>(i);
    auto* key = new QTableWidgetItem(q(n.key));
    key->setFlags(Qt::ItemIsEnabled | Qt::ItemIsUserCheckable | Qt::ItemIsSelectable);
    // What a researcher tunes first: the behavior's own parameters.
    key->setCheckState(n.key.find("behavior.params.") != std::string::npos ? Qt::Checked : Qt::Unchecked);
    key->setToolTip(q(n.spec.description));
    table_->setItem(r, col_key, key);
    auto* value = new QTableWidgetItem(q(Parameter::format(n.value)));
    value->setFlags(Qt::ItemIsEnabled);
    table_->setItem(r, col_value, value);
    table_->setItem(r, col_min, new QTableWidgetItem(q(Parameter::format(n.spec.min))));
    table_->setItem(r, col_max, new QTableWidgetItem(q(Parameter::format(n.spec.max))));
    auto* log = new QTableWidgetItem;
    log->setFlags(Qt::ItemIsEnabled | Qt::ItemIsUserCheckable);
    log->setCheckState(n.log ? Qt::Checked : Qt::Unchecked);
    table_->setItem(r, col_log, log);
    auto* allowed = new QTableWidgetItem(q(n.spec.range()));
    allowed->setFlags(Qt::ItemIsEnabled);
    table_->setItem(r, col_allowed, allowed);
  }
  table_->resizeColumnsToContents();
  fill_objectives();
  show_message(QString("%1 numbers of %2 can be tuned; its behavior's parameters are ticked").arg(numbers_.size()).arg(q(base_->name)), false);
  return {};
}

void TunePage::fill_objectives() {
  const QString was = objective_->currentText();
  objective_->clear();
  try {
    const DataColumns columns = data_columns(*base_, *host_);
    for (const std::string& c : columns.outcome) objective_->addItem(q(c));
    for (const std::string& c : columns.summary)
      if (c != "time" && objective_->findText(q(c)) < 0) objective_->addItem(q(c));
  } catch (const std::exception& e) {
    show_message(q(e.what()));
  }
  objective_->setCurrentText(was.isEmpty() || objective_->findText(was) < 0 ? "targets_found" : was);
}

bool TunePage::set_parameter(const std::string& key, bool tuned, double min, double max) {
  for (int r = 0; r < table_->rowCount(); ++r) {
    if (table_->item(r, col_key)->text().toStdString() != key) continue;
    table_->item(r, col_key)->setCheckState(tuned ? Qt::Checked : Qt::Unchecked);
    if (!std::isnan(min)) table_->item(r, col_min)->setText(q(Parameter::format(min)));
    if (!std::isnan(max)) table_->item(r, col_max)->setText(q(Parameter::format(max)));
    return true;
  }
  return false;
}

std::string TunePage::base_json() const {
  json test = json::parse(resolved_json(*base_, *host_));
  test.erase("seed");  // the tune gives each world its paired seed
  test.erase("repeat");
  return test.dump();
}

std::string TunePage::tune_json(std::string* why, std::string* canonical) const {
  if (!base_) return *why = "no test to tune yet: From sandbox takes the sandbox's", std::string();
  json params = json::object();
  for (int r = 0; r < table_->rowCount(); ++r) {
    if (table_->item(r, col_key)->checkState() != Qt::Checked) continue;
    const TunableNumber& n = numbers_[static_cast<std::size_t>(r)];
    json p = json::object();
    for (const int c : {col_min, col_max}) {
      const char* end = c == col_min ? "min" : "max";
      bool ok = false;
      const QString text = table_->item(r, c)->text().trimmed();
      const double v = text.toDouble(&ok);
      if (!ok) return *why = "tune: " + n.key + ": " + end + " \"" + text.toStdString() + "\" is not a number (allowed: " + n.spec.range() + ")", std::string();
      // The declared end is the default; a whole number is written as typed ("-1", not "-1.0").
      if (v != (c == col_min ? n.spec.min : n.spec.max)) p[end] = v == std::floor(v) && std::fabs(v) < 9e15 ? json(static_cast<std::int64_t>(v)) : json(v);
    }
    if (const bool log = table_->item(r, col_log)->checkState() == Qt::Checked; log != n.log) p["log"] = log;
    params[n.key] = p;
  }
  if (params.empty()) return *why = "tune: nothing to tune (allowed: tick one or more numbers in the table)", std::string();
  json seed;
  try {
    seed = json::parse(seed_->text().trimmed().toStdString());
  } catch (const std::exception&) {
  }
  if (!seed.is_number_unsigned() || seed.get<std::uint64_t>() > max_seed)
    return *why = "tune: seed: \"" + seed_->text().trimmed().toStdString() + "\" is not a seed (allowed: whole number in [0, " + std::to_string(max_seed) + "])", std::string();
  json j{{"test", json::parse(base_json())},
         {"parameters", params},
         {"objective", {{"column", objective_->currentText().toStdString()}, {"goal", goal_->currentText().toStdString()},
                        {"aggregate", aggregate_->currentText().toStdString()}}},
         {"algorithm", algorithm_->currentText().toStdString()},
         {"seed", seed},
         {"budget", {{"evaluations", evaluations_->whole()}}},
         {"worlds", worlds_->whole()},
         {"validation", {{"worlds", validation_->whole()}}}};
  if (!racing_->isChecked() || worlds_->value() < 2) j["racing"] = false;
  const std::string text = j.dump(2) + "\n";
  // Checked as salsa tune checks it, so a run is never started only to be refused.
  const auto spec = check_tune(text, *host_, why);
  if (!spec) return {};
  if (canonical) *canonical = spec->canonical;
  return text;
}

std::string TunePage::save(const QString& file) {
  std::string why;
  const std::string text = tune_json(&why);
  if (text.empty()) return show_message(q(why)), why;
  why = save_checked(file.toStdString(), text, [this](const fs::path& aside) -> std::string {
    load_tune(aside, *host_);  // throws what salsa tune would refuse
    return {};
  });
  show_message(why.empty() ? QString("saved %1 (salsa tune %1 runs it)").arg(file) : q(why), !why.empty());
  return why;
}

// ---------------------------------------------------------------- running

std::string TunePage::run(const QString& out) {
  if (running()) return show_message("a tune is running; stop it first"), "a tune is running";
  std::string why, canonical;
  if (tune_json(&why, &canonical).empty()) return show_message(q(why)), why;
  const QString dir = QFileInfo(out).absoluteFilePath();
  const QString file = dir + ".tune.json";
  // As salsa tune decides, before anything is written: a folder that records this tune resumes it;
  // another tune's folder is refused (its FOLDER.tune.json is left as it is).
  const fs::path record = dir.toStdString() + "/tune.json";
  const bool resume = fs::exists(record);
  if (resume && text_of(record) != canonical + "\n") {
    why = dir.toStdString() + ": holds another tune (allowed: another output folder)";
    return show_message(q(why)), why;
  }
  if (why = save(file); !why.empty()) return why;
  out_ = dir;
  budget_ = static_cast<std::size_t>(evaluations_->value());
  for (QXYSeries* s : std::initializer_list<QXYSeries*>{best_, defaults_, scores_}) s->clear();
  load_best_button_->setEnabled(false);
  QStringList args{"tune", file, "--out", dir, "--jobs", QString::number(jobs_->whole())};
  if (resume) args << "--resume";  // finished tests are read back: the tune continues exactly
  for (const auto& d : plugin_dirs_) args << "--plugin-dir" << q(d.string());
  process_->start(args);
  run_button_->setEnabled(false);
  stop_button_->setEnabled(true);
  update_chart();
  show_message(QString("tuning %1 into %2").arg(resume ? "again (resumed)" : "", dir).simplified(), false);
  return {};
}

void TunePage::stop() { process_->stop(); }

bool TunePage::running() const { return process_->running(); }

bool TunePage::wait(int ms) { return process_->wait(ms); }

QString TunePage::log_text() const { return log_->toPlainText(); }

std::string TunePage::open_results(const QString& out) {
  const QString dir = QFileInfo(out).absoluteFilePath();
  if (!QFileInfo::exists(dir + "/tune.json")) {
    const std::string why = dir.toStdString() + ": no tune.json there (allowed: an output folder salsa tune wrote)";
    return show_message(q(why)), why;
  }
  out_ = dir;
  budget_ = 0;
  update_chart();
  load_best_button_->setEnabled(QFileInfo::exists(dir + "/best.json"));
  show_message(QFileInfo::exists(dir + "/best.json") ? "tune in " + dir + ": finished (Load best puts the winner in the sandbox)"
                                                     : "tune in " + dir + ": not finished (Run into it with the same settings resumes it)",
               false);
  return {};
}

std::string TunePage::load_best() {
  const fs::path best = (out_ + "/best.json").toStdString();
  try {
    const std::vector<TestSpec> tests = load_tests(best, *host_);
    if (tests.empty()) throw InputError(best.string() + ": holds no test");
    if (load_into_sandbox_) load_into_sandbox_(tests.front());
  } catch (const std::exception& e) {
    return show_message(q(e.what())), e.what();
  }
  show_message("the winner is in the sandbox, on the first tuning world (" + q(best.string()) + ")", false);
  return {};
}

void TunePage::update_chart() {
  if (out_.isEmpty()) return;
  const fs::path dir = out_.toStdString();
  bool maximise = goal_->currentText() == "max";
  try {  // the tune's own settings, when it has written them
    if (fs::exists(dir / "tune.json")) {
      const json j = json::parse(text_of(dir / "tune.json"));
      if (j.contains("objective")) maximise = j["objective"].value("goal", "max") == "max";
      if (j.contains("budget") && j["budget"].contains("evaluations")) budget_ = j["budget"]["evaluations"].get<std::size_t>();
    }
  } catch (const std::exception&) {
  }
  struct Point {
    double evaluations, score;
  };
  std::vector<Point> complete;
  std::optional<double> defaults;
  double used = 0;
  try {
    if (!fs::exists(dir / "candidates.csv")) return;
    CsvReader csv(dir / "candidates.csv");
    const std::size_t id = csv.column("candidate"), status = csv.column("status"), evaluations = csv.column("evaluations");
    const std::size_t score = csv.header().size() - 1;  // the (first and only) objective: the last column
    while (csv.next()) {
      used = std::max(used, csv.number(evaluations));
      const auto s = csv.optional_number(score);
      if (csv[id] == "0" && s) defaults = *s;
      if (csv[status] == "complete" && s) complete.push_back({csv.number(evaluations), *s});
    }
  } catch (const std::exception&) {
    return;  // written again after the next generation
  }
  std::stable_sort(complete.begin(), complete.end(), [](const Point& a, const Point& b) { return a.evaluations < b.evaluations; });
  QList<QPointF> best, dots;
  std::optional<double> so_far;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Point& p : complete) {
    so_far = !so_far ? p.score : maximise ? std::max(*so_far, p.score) : std::min(*so_far, p.score);
    if (!best.isEmpty()) best.append(QPointF(p.evaluations, best.back().y()));  // a step: the best holds until bettered
    best.append(QPointF(p.evaluations, *so_far));
    dots.append(QPointF(p.evaluations, p.score));
    lo = std::min(lo, p.score);
    hi = std::max(hi, p.score);
  }
  const double x_max = std::max({10.0, used, static_cast<double>(budget_)});
  if (!best.isEmpty()) best.append(QPointF(used, best.back().y()));
  best_->replace(best);
  scores_->replace(dots);
  x_->setRange(0, x_max);
  x_->applyNiceNumbers();
  defaults_->replace(defaults ? QList<QPointF>{{0, *defaults}, {x_->max(), *defaults}} : QList<QPointF>{});
  if (defaults) lo = std::min(lo, *defaults), hi = std::max(hi, *defaults);
  if (std::isfinite(lo)) {
    const double pad = std::max(1e-9, (hi - lo) * 0.08 + 1e-6 * std::max(std::fabs(lo), std::fabs(hi)));
    y_->setRange(lo - pad, hi + pad);
    y_->applyNiceNumbers();
  }
  chart_view_->chart()->setTitle(QString("Best so far: %1 (%2)")
                                     .arg(so_far ? q(Parameter::format(*so_far)) : QString("none yet"))
                                     .arg(defaults ? "defaults " + q(Parameter::format(*defaults)) : QString("defaults running")));
  progress_->setRange(0, static_cast<int>(std::max<std::size_t>(budget_, 1)));
  progress_->setValue(static_cast<int>(std::min<double>(used, static_cast<double>(std::max<std::size_t>(budget_, 1)))));
  progress_->setFormat(budget_ ? "%v / %m evaluations" : QString("%1 evaluations").arg(used));
}

}  // namespace salsa::gui
