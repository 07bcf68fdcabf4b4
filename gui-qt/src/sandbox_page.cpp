// The sandbox page: the view, its run controls, files, settings, status figures and inspector (its forms: sandbox_forms.cpp).
#include "sandbox_page.hpp"

#include <QAbstractSpinBox>
#include <QComboBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLabel>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include "number_field.hpp"
#include <QVBoxLayout>
#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "inspector_text.hpp"
#include "live_charts.hpp"
#include "param_panel.hpp"
#include "recorder.hpp"
#include "save_checked.hpp"
#include "salsa/core/files/names.hpp"

namespace salsa::gui {
namespace {

using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

QString q(const std::string& s) { return QString::fromStdString(s); }

// The sandbox's first scene: a small forest, enough drones and trees to see the behavior work.
constexpr const char* first_test = R"({"name": "sandbox", "behavior": "pheromone_avoidance", "drones": 20,
  "map": {"name": "forest", "params": {"size": 500}}, "targets": {"kind": "tree", "count": 500},
  "time": 3600, "seed": 1})";

}  // namespace

SandboxPage::SandboxPage(std::shared_ptr<const PluginHost> host, QWidget* parent)
    : QWidget(parent), host_(std::move(host)), engine_(host_) {
  view_ = new SwarmView;
  connect(view_, &SwarmView::drone_clicked, this, [this](std::optional<std::uint32_t> id) { engine_.select(id); });
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(view_);
  build_controls();
  connect(&timer_, &QTimer::timeout, this, &SandboxPage::refresh);
  timer_.start(16);
  fps_since_ = slow_refresh_ = Clock::now();
}

SandboxPage::~SandboxPage() {
  if (recorder_) recorder_->stop();
}

std::vector<QLabel*> SandboxPage::status_labels() const {
  return {status_time_, status_speed_, status_fps_, status_found_, status_inexact_};
}

void SandboxPage::set_active(bool active) {
  active_ = active;
  for (QLabel* l : {status_time_, status_speed_, status_fps_, status_found_}) l->setVisible(active);
  if (!active) status_inexact_->hide();
}

std::string SandboxPage::open_test_spec(const TestSpec& test) {
  const TestSpec previous = file_base_;
  file_base_ = test;
  if (const std::string why = load(file_base_); !why.empty()) {
    file_base_ = previous;
    return why;
  }
  if (!test.changes.empty())
    show_message(QString("'%1': its %2 timed changes apply as it runs, as in salsa run").arg(q(test.name)).arg(test.changes.size()), false);
  return {};
}

void SandboxPage::fill_plugin_lists() {
  const bool was = updating_;
  updating_ = true;
  auto refill = [](QComboBox* box, const QStringList& names) {
    const QString keep = box->currentText();
    box->clear();
    box->addItems(names);
    if (box->findText(keep) < 0 && !keep.isEmpty()) box->addItem(keep);  // still running, though gone from the folders
    box->setCurrentText(keep);
  };
  QStringList behaviors, maps, kinds;
  for (const auto& e : host_->behaviors()) behaviors << q(e.factory.name);
  for (const auto& e : host_->maps())
    if (e.factory.name != "json") maps << q(e.factory.name);
  for (const auto& e : host_->target_kinds()) kinds << q(e.factory.name);
  refill(behavior_, behaviors);
  refill(map_, maps);
  refill(target_kind_, kinds);
  updating_ = was;
}

void SandboxPage::use_plugins(std::shared_ptr<const PluginHost> host, const QStringList& rebuilt) {
  host_ = std::move(host);
  fill_plugin_lists();
  // The running behaviors (of any group) whose files were rebuilt: each group running one reloads.
  std::vector<std::string> reload;
  std::string what;  // "behavior 'a' from /x/liba.so", for the messages
  for (const std::string& running : engine_.behavior_names()) {
    const auto& all = host_->behaviors();
    if (std::find(reload.begin(), reload.end(), running) != reload.end() ||
        std::none_of(all.begin(), all.end(), [&](const auto& e) { return e.factory.name == running; }))
      continue;
    const std::string file = host_->behavior(running).plugin().file.string();
    if (!rebuilt.contains(q(file))) continue;
    reload.push_back(running);
    what += (what.empty() ? "behavior '" : ", behavior '") + running + "' from " + file;
  }
  const bool reloading = !reload.empty();
  pending_.push_back({engine_.use_plugins(host_, std::move(reload)), [this, reloading, what](const std::string& why) {
                        if (!why.empty()) return show_message(q(what + " was not reloaded: " + why));
                        if (!reloading) return show_message(QString("plugins rescanned: %1 files").arg(host_->plugins().size()), false);
                        if (auto t = engine_.current_test()) {
                          loaded_ = *t;
                          show_test(*t);  // the new code's parameters
                        }
                        show_message(q("reloaded " + what + ": the simulation goes on with the new code"), false);
                      }});
}

namespace {
/// Keeps a vertical scroll area as wide as its panel's minimum (plus the scroll bar), as rows come and go.
class FitWidth : public QObject {
 public:
  explicit FitWidth(QScrollArea* area) : QObject(area), area_(area) {}
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (event->type() == QEvent::LayoutRequest || event->type() == QEvent::Show) {
      const int width = static_cast<QWidget*>(watched)->minimumSizeHint().width() +
                        area_->verticalScrollBar()->sizeHint().width() + 2 * area_->frameWidth();
      if (area_->minimumWidth() != width) area_->setMinimumWidth(width);
    }
    return false;
  }

 private:
  QScrollArea* area_;
};
}  // namespace

void SandboxPage::build_controls() {
  auto* panel = new QWidget;
  auto* column = new QVBoxLayout(panel);
  build_forms(column);

  auto* run = new QGroupBox("Run");
  auto* run_layout = new QVBoxLayout(run);
  auto* buttons = new QHBoxLayout;
  run_button_ = new QPushButton("Start");
  auto* step_button = new QPushButton("Step");
  auto* reset_button = new QPushButton("Reset");
  for (auto* b : {run_button_, step_button, reset_button}) buttons->addWidget(b);
  run_layout->addLayout(buttons);
  auto* speed = new QHBoxLayout;
  pacing_ = new QComboBox;
  pacing_->setObjectName("pacing");
  pacing_->addItems({"real time", "steps per frame", "larger time step ×", "as fast as possible"});
  pacing_->setToolTip("real time; N exact steps per frame; a step N times longer (fast, inexact); or flat out");
  pacing_amount_ = new NumberField({"pacing_amount", 4, 1, 1000, "", "", 1});
  pacing_amount_->setValue(4);
  pacing_amount_->setEnabled(false);
  speed->addWidget(pacing_, 1);
  speed->addWidget(pacing_amount_);
  run_layout->addLayout(speed);
  column->insertWidget(0, run);  // first: the buttons used most stay in sight
  column->addStretch();

  for (QWidget* input : panel->findChildren<QWidget*>())
    if (qobject_cast<QAbstractSpinBox*>(input) || qobject_cast<QComboBox*>(input)) wheel_scrolls_unless_focused(input);
  auto* scroll = new QScrollArea;
  scroll->setWidget(panel);
  scroll->setWidgetResizable(true);
  // Never sideways: the panel is as wide as its widest row needs (rebuilt rows included), so Tab never
  // scrolls it to a field cut off at the right.
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  panel->installEventFilter(new FitWidth(scroll));
  controls_ = scroll;

  charts_ = new LiveCharts;
  inspector_ = new QPlainTextEdit;
  inspector_->setReadOnly(true);
  inspector_->setPlaceholderText("Click a drone to inspect it.");
  inspector_->setMaximumHeight(220);

  status_time_ = new QLabel;
  status_speed_ = new QLabel;
  status_fps_ = new QLabel;
  status_found_ = new QLabel;
  status_inexact_ = new QLabel("inexact: larger time step");
  status_inexact_->setStyleSheet("color: #b00020; font-weight: bold");
  status_inexact_->hide();

  connect(run_button_, &QPushButton::clicked, this, &SandboxPage::toggle_run);
  connect(step_button, &QPushButton::clicked, this, &SandboxPage::step);
  connect(reset_button, &QPushButton::clicked, this, &SandboxPage::reset);
  connect(pacing_, &QComboBox::currentIndexChanged, this, &SandboxPage::set_pacing);
  connect(pacing_amount_, &NumberField::valueChanged, this, &SandboxPage::set_pacing);
}

void SandboxPage::show_message(const QString& text, bool error) {
  last_message_ = text;
  Q_EMIT message(text, error);
  if (!error) return;
  // Not modal-blocking: the simulation and the view go on while the message is up.
  auto* box = new QMessageBox(QMessageBox::Warning, "salsa", text, QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

// ---------------------------------------------------------------- start states

std::string SandboxPage::load(const TestSpec& test) {
  reload_due_ = false;  // this load supersedes an edit still waiting
  const std::string why = engine_.load(test).get();  // building a world takes a moment; the user asked for it
  if (!why.empty()) {
    show_message(q(why));
    if (loaded_) show_test(*engine_.current_test());  // the controls go back to what runs
    return why;
  }
  loaded_ = test;
  past_time_told_ = false;
  show_test(test);
  view_->fit();
  return {};
}

std::string SandboxPage::open_test(const QString& file) {
  std::vector<TestSpec> tests;
  try {
    tests = load_tests(file.toStdString(), *host_);
  } catch (const std::exception& e) {
    show_message(q(e.what()));
    return e.what();
  }
  if (tests.empty()) {
    show_message(file + ": holds no test");
    return (file + ": holds no test").toStdString();
  }
  const TestSpec previous = file_base_;
  file_base_ = tests.front();
  if (const std::string why = load(tests.front()); !why.empty()) {
    file_base_ = previous;
    return why;
  }
  if (tests.size() > 1) show_message(QString("%1 holds %2 tests: the first, '%3', is loaded").arg(file).arg(tests.size()).arg(q(tests.front().name)), false);
  if (!tests.front().changes.empty())
    show_message(QString("%1: its %2 timed changes apply as it runs, as in salsa run").arg(file).arg(tests.front().changes.size()), false);
  return {};
}

std::string SandboxPage::open_map(const QString& file) {
  try {
    load_map_file(file.toStdString(), *host_, loaded_ ? loaded_->groups[0].drone.radius : 1);  // the CLI's checks, before anything changes
  } catch (const std::exception& e) {
    show_message(q(e.what()));
    return e.what();
  }
  const QString previous = map_file_;
  map_file_ = QFileInfo(file).absoluteFilePath();
  std::string why;
  const auto spec = spec_from_controls(&why);
  if (!spec || !(why = load(*spec)).empty()) {
    map_file_ = previous;
    if (!spec) show_message(q(why));
    return why;
  }
  return {};
}

std::string SandboxPage::save_test(const QString& file) {
  std::string why;
  auto test = engine_.as_test(&why);
  if (!test) {
    show_message(q(why));
    return why;
  }
  // The file's name names the test (and its output folder), when it is a valid name.
  const std::string stem = QFileInfo(file).completeBaseName().toStdString();
  if (test_name_problem(stem).empty()) test->name = stem;
  std::ofstream out(file.toStdString(), std::ios::binary);
  out << resolved_json(*test, *host_);
  out.close();
  if (!out) {
    why = file.toStdString() + ": cannot write the test";
    show_message(q(why));
    return why;
  }
  show_message(QString("saved %1: %2 s with %3 live changes; replay it with `salsa run %1`")
                   .arg(file).arg(test->time).arg(test->changes.size()), false);
  return {};
}

std::string SandboxPage::save_screenshot(const QString& file) {
  QString error;
  if (!save_png(view_->screenshot(), file, &error)) {
    show_message(error);
    return error.toStdString();
  }
  show_message("saved " + file, false);
  return {};
}

void SandboxPage::ask_open_test() {
  const QString f = QFileDialog::getOpenFileName(this, "Open a test", {}, "Tests (*.json)");
  if (!f.isEmpty()) open_test(f);
}

void SandboxPage::ask_open_map() {
  const QString f = QFileDialog::getOpenFileName(this, "Open a map", {}, "JSON maps (*.json)");
  if (!f.isEmpty()) open_map(f);
}

void SandboxPage::ask_save_test() {
  std::string why;
  if (!engine_.as_test(&why)) return show_message(q("nothing to save as a test: " + why));  // before a name is asked for
  const QString f = ask_save_file(this, "Save as test", "sandbox.json", "Tests (*.json)", [](const QString& file) {
    const std::string stem = QFileInfo(file).completeBaseName().toStdString();
    return test_name_problem(stem).empty() ? std::string() : "the file's name names the test: " + test_name_problem(stem);
  });
  if (!f.isEmpty()) save_test(f);
}

void SandboxPage::ask_screenshot() {
  const QString f = ask_save_file(this, "Screenshot", "salsa.png", "PNG images (*.png)", [](const QString& file) {
    return file.endsWith(".png", Qt::CaseInsensitive) ? std::string() : "a screenshot is a PNG file: its name ends in .png";
  });
  if (!f.isEmpty()) save_screenshot(f);
}

// ---------------------------------------------------------------- live changes and running

void SandboxPage::live_change(const std::string& key, double value) {
  pending_.push_back({engine_.set(key, value), [this](const std::string& why) {
                        if (why.empty()) return;
                        show_message(q(why));
                        if (auto t = engine_.current_test()) show_test(*t);  // back to what runs
                      }});
}

void SandboxPage::start() {
  engine_.start();
  run_button_->setText("Pause");
}
void SandboxPage::pause() {
  engine_.pause();
  run_button_->setText("Start");
}
void SandboxPage::toggle_run() {
  const auto snap = engine_.snapshot();
  if (snap->state == RunState::running) pause();
  else start();
}
void SandboxPage::step() {
  run_button_->setText("Start");
  pending_.push_back({engine_.step_once(), [this](const std::string& why) {
                        if (!why.empty()) show_message(q(why));
                      }});
}
void SandboxPage::reset() {
  run_button_->setText("Start");
  past_time_told_ = false;
  pending_.push_back({engine_.reset(), [this](const std::string& why) {
                        if (!why.empty()) show_message(q(why));
                        else if (loaded_) show_test(*loaded_);
                      }});
}

void SandboxPage::set_pacing() {
  Pacing p;
  const int mode = pacing_->currentIndex();
  p.mode = mode == 0 ? Pacing::real_time : mode == 1 ? Pacing::steps_per_frame : mode == 2 ? Pacing::real_time : Pacing::fastest;
  pacing_amount_->setEnabled(mode == 1 || mode == 2);
  if (mode == 1) p.steps = static_cast<int>(pacing_amount_->whole());
  if (mode == 2) {  // the larger step runs as fast as it can: it is there for speed
    p.mode = Pacing::fastest;
    p.dt_factor = static_cast<int>(pacing_amount_->whole());
  }
  pending_.push_back({engine_.set_pacing(p), [this](const std::string& why) {
                        if (why.empty()) return;
                        show_message(q(why));
                        const bool was = updating_;
                        updating_ = true;
                        pacing_->setCurrentIndex(0);
                        pacing_amount_->setEnabled(false);
                        updating_ = was;
                        engine_.set_pacing({});
                      }});
}

void SandboxPage::toggle_recording() {
  if (recorder_) {
    recorder_->stop();
    const int frames = recorder_->frames();
    QString error;
    const QString video = recorder_->make_video(&error);
    recorder_.reset();
    Q_EMIT recording_changed(false);
    show_message(video.isEmpty() ? QString("recorded %1 frames; %2").arg(frames).arg(error)
                                 : QString("recorded %1 frames: %2").arg(frames).arg(video),
                 false);
    return;
  }
  const QString folder = QFileDialog::getExistingDirectory(this, "Record PNG frames into");
  if (folder.isEmpty()) return;
  bool ok = false;
  const double interval = QInputDialog::getDouble(this, "Recording", "One frame every (simulated seconds):", 0.1, 0.001, 3600, 3, &ok);
  if (!ok) return;
  QSize size = view_->size();
  size = QSize(size.width() / 2 * 2, size.height() / 2 * 2);  // even: video encoders need it
  recorder_ = std::make_unique<Recorder>(engine_, folder, interval, size, view_->options(), view_->world_to_px());
  recorder_->start();
  Q_EMIT recording_changed(true);
  show_message(QString("recording a frame every %1 s of simulated time into %2").arg(interval).arg(folder), false);
}

// ---------------------------------------------------------------- showing

QString SandboxPage::inspector_text() const { return inspector_->toPlainText(); }

void SandboxPage::poll() {
  for (std::size_t i = 0; i < pending_.size();) {
    if (pending_[i].answer.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      ++i;
      continue;
    }
    Pending done = std::move(pending_[i]);
    pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(i));
    done.then(done.answer.get());
  }
  if (reload_due_) reload_from_controls();
  // A change of the timeline applied (the test's own, at its time): the controls show what runs now.
  if (const auto snap = engine_.snapshot(); loaded_ && snap->changes_applied != changes_shown_) {
    changes_shown_ = snap->changes_applied;
    if (auto t = engine_.current_test()) show_test(*t);
  }
}

void SandboxPage::refresh() {
  poll();
  auto snap = engine_.snapshot();
  if (snap != shown_) {
    shown_ = snap;
    view_->show_snapshot(snap);
    ++frames_;
  }
  // The test's time: the sandbox pauses there once and says so; Start runs on past it, marked below.
  const double end = loaded_ ? loaded_->time : 0;
  const bool past = loaded_ && snap->time >= end - 1e-9 && snap->test_name == loaded_->name;
  // The engine paused itself on the step that reached it (pacing cannot carry it further).
  if (past && !past_time_told_) {
    past_time_told_ = true;
    if (snap->state != RunState::running) run_button_->setText("Start");
    show_message(QString("paused at t = %1 s, the test's time (Start runs on past it; Save as test keeps the time reached)")
                     .arg(snap->time, 0, 'f', 1),
                 false);
  }
  const auto now = Clock::now();
  if (now - slow_refresh_ < std::chrono::milliseconds(250)) return;  // text and plots: a few times a second
  const double since = std::chrono::duration<double>(now - fps_since_).count();
  if (since >= 1) {
    fps_ = frames_ / since;
    frames_ = 0;
    fps_since_ = now;
  }
  slow_refresh_ = now;
  charts_->show_rows(snap->stats);
  const QGroupBox* comm = model_box("comm");
  if (comm_note_) comm_note_->setText(!comm || !comm->isChecked() ? QString()
                      : !snap->links.empty()
                          ? QString("%1 messages delivered for the next step, drawn as links (View > Communication links)").arg(snap->links.size())
                          : "No messages in flight, so no links drawn: a link is a message delivered, and only a behavior that "
                            "broadcasts sends any (" + behavior_->currentText() + " has sent none this step)");
  const bool beyond = past && snap->time > end + 1e-9;  // ran on with Start, not just at the end
  status_time_->setText(beyond ? QString("t = %1 s, past the test's %2 s").arg(snap->time, 0, 'f', 1).arg(end)
                               : QString("t = %1 s").arg(snap->time, 0, 'f', 1));
  status_time_->setStyleSheet(beyond ? "color: #b00020; font-weight: bold" : "");
  status_speed_->setText(QString("%1× real time").arg(snap->speed, 0, 'f', snap->speed < 10 ? 2 : 0));
  status_fps_->setText(QString("%1 FPS").arg(fps_, 0, 'f', 0));
  const std::size_t targets = snap->found.size();
  status_found_->setText(targets ? QString("found %1 / %2 (%3 %)").arg(snap->targets_found).arg(targets)
                                       .arg(100.0 * static_cast<double>(snap->targets_found) / static_cast<double>(targets), 0, 'f', 1)
                                 : QString("no targets"));
  status_inexact_->setVisible(snap->inexact && active_);
  if (snap->state == RunState::failed && snap->error != last_error_shown_) {
    last_error_shown_ = snap->error;
    run_button_->setText("Start");
    show_message(q(snap->error));
  }
  if (snap->state != RunState::running && run_button_->text() == "Pause") run_button_->setText("Start");
  // The fail button names the inspected drone while it flies.
  fail_target_.reset();
  if (snap->selected && snap->status_of(snap->selected->id) == DroneStatus::flying) fail_target_ = snap->selected->id;
  fail_->setEnabled(fail_target_ && snap->state != RunState::failed);
  fail_->setText(fail_target_ ? QString("Fail drone %1").arg(*fail_target_) : QString("Fail the inspected drone"));
  // Longer than its box: a person scrolled down to a model's lines stays there as the values change.
  if (const QString text = inspection_text(*snap); text != inspector_->toPlainText()) {
    const int at = inspector_->verticalScrollBar()->value();
    inspector_->setPlainText(text);
    inspector_->verticalScrollBar()->setValue(at);
  }
}

// ---------------------------------------------------------------- settings

void SandboxPage::restore_settings() {
  QSettings settings;
  file_base_ = parse_test(first_test, "sandbox", *host_);
  // The last session's start state, if it still parses with the plugins there are now. If not, say
  // what was replaced and why: a relaunch without its --plugin-dir must not swap behaviors silently.
  const QString last = settings.value("sandbox/test").toString();
  QString replaced;
  if (!last.isEmpty()) {
    try {
      file_base_ = parse_test(last.toStdString(), "last session", *host_);
    } catch (const std::exception& e) {
      std::string behavior;
      try {
        const json b = json::parse(last.toStdString()).at("behavior");  // "name" or {"name": ...}
        behavior = b.is_string() ? b.get<std::string>() : b.at("name").get<std::string>();
      } catch (const std::exception&) {
      }
      replaced = QString("the last session's test (behavior '%1') was not restored: %2; the first scene runs instead "
                         "(start salsa-gui with the same --plugin-dir to get it back)")
                     .arg(q(behavior), q(e.what()));
    }
  }
  if (!load(file_base_).empty()) {
    file_base_ = parse_test(first_test, "sandbox", *host_);
    load(file_base_);
    if (replaced.isEmpty()) replaced = "the last session's test did not load (see the message); the first scene runs instead";
  }
  if (!replaced.isEmpty()) show_message(replaced, false);
}

void SandboxPage::save_settings() {
  QSettings settings;
  if (auto t = engine_.current_test()) {
    t->changes.clear();
    settings.setValue("sandbox/test", q(resolved_json(*t, *host_)));
  }
}

}  // namespace salsa::gui
