#include "main_window.hpp"

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QKeySequence>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QScrollArea>
#include <QSignalBlocker>
#include <QSettings>
#include <QSpinBox>
#include <QStackedWidget>
#include <QStatusBar>
#include <QToolBar>
#include <QActionGroup>
#include <QVBoxLayout>
#include <fstream>
#include <nlohmann/json.hpp>

#include "live_charts.hpp"
#include "map_editor.hpp"
#include "plugins.hpp"
#include "queue_page.hpp"
#include "param_panel.hpp"
#include "recorder.hpp"
#include "salsa/core/names.hpp"

namespace salsa::gui {
namespace {

using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

QString q(const std::string& s) { return QString::fromStdString(s); }

json params_json(const ParamPanel* panel) {
  json out = json::object();
  for (const Parameter& p : panel->schema()) out[p.name] = panel->value(p.name);
  return out;
}

json drone_json(const DroneConfig& d) {
  return {{"name", d.name},           {"camera_range", d.camera_range}, {"obstacle_range", d.obstacle_range},
          {"detection_range", d.detection_range}, {"max_speed", d.max_speed}, {"max_force", d.max_force},
          {"radius", d.radius},       {"mass", d.mass},                 {"obstacle_rays", d.obstacle_rays}};
}

double drone_value(const DroneConfig& d, const std::string& name) { return *drone_property(d, name); }

// The sandbox's first scene: a small forest, enough drones and trees to see the behavior work.
constexpr const char* first_test = R"({"name": "sandbox", "behavior": "pheromone_avoidance", "drones": 20,
  "map": {"name": "forest", "params": {"size": 500}}, "targets": {"kind": "tree", "count": 500},
  "time": 3600, "seed": 1})";

const char* const shortcuts[][2] = {
    {"Space", "start / pause"},       {"Right, S", "one step"},         {"R", "reset to the start state"},
    {"+ / −, wheel", "zoom"},         {"0, F", "fit the map"},          {"drag", "pan"},
    {"click a drone", "inspect it"},  {"Ctrl+O", "open a test"},        {"Ctrl+M", "open a map"},
    {"Ctrl+S", "save as test"},       {"Ctrl+P", "screenshot"},         {"Ctrl+R", "start / stop recording"},
    {"Ctrl+1 / 2 / 3", "sandbox / queue / map creator"}, {"F5", "rescan plugin folders"},
    {"V L P O S B", "map creator: select, line, polygon, hollow, spawn, bounds"},
    {"Ctrl+Z / Ctrl+Shift+Z", "map creator: undo / redo"}, {"Delete / Esc", "map creator: delete the selection / drop the polygon being drawn"},
    {"Ctrl+Q", "quit"},
};

}  // namespace

MainWindow::MainWindow(std::shared_ptr<const PluginHost> host, std::vector<std::filesystem::path> plugin_dirs, QWidget* parent)
    : QMainWindow(parent), host_(host), engine_(host), editor_host_(host) {
  setWindowTitle("salsa — sandbox");
  plugins_ = new PluginManager(plugin_dirs, host_, this);
  connect(plugins_, &PluginManager::plugins_changed, this,
          [this](std::shared_ptr<const PluginHost> h, const QStringList& rebuilt) { use_plugins(std::move(h), rebuilt); });
  // In the status bar, not a dialog: a build still writing the file causes these, and the next write retries.
  connect(plugins_, &PluginManager::reload_failed, this, [this](const QString& why) { show_message(why, false); });
  view_ = new SwarmView;
  connect(view_, &SwarmView::drone_clicked, this, [this](std::optional<std::uint32_t> id) { engine_.select(id); });
  queue_ = new QueuePage(host_, plugin_dirs);
  queue_->set_sandbox([this](std::string* why) -> std::optional<TestSpec> {
    auto t = engine_.current_test();
    if (!t && why) *why = "no test loaded in the sandbox";
    return t;
  });
  queue_->set_load_into_sandbox([this](const TestSpec& t) { open_test_spec(t); });
  map_editor_ = new MapEditor(*editor_host_);
  connect(map_editor_, &MapEditor::map_saved, this, [this](const QString& file) {
    show_message("saved " + file + ": \"Map file…\" in the sandbox, or a test's \"map\": {\"file\": ...}, uses it", false);
  });
  connect(map_editor_, &MapEditor::use_in_sandbox, this, [this](const QString& file) {
    if (open_map(file).empty()) set_mode(Mode::sandbox);
  });
  pages_ = new QStackedWidget;
  pages_->addWidget(view_);
  pages_->addWidget(queue_);
  pages_->addWidget(map_editor_);
  setCentralWidget(pages_);
  build_controls();
  build_menus();
  restore_settings();
  connect(&timer_, &QTimer::timeout, this, &MainWindow::refresh);
  timer_.start(16);
  fps_since_ = slow_refresh_ = Clock::now();
}

MainWindow::MainWindow(const PluginHost& host, QWidget* parent)
    : MainWindow(std::shared_ptr<const PluginHost>(&host, [](const PluginHost*) {}), {}, parent) {}

void MainWindow::show_plugins() {
  auto* d = new PluginsDialog(*plugins_, this);
  d->setAttribute(Qt::WA_DeleteOnClose);
  d->show();
}

void MainWindow::set_mode(Mode m) {
  if (m == mode_) return;
  // The sandbox's docks go with it (the simulation keeps its state, running or paused).
  if (mode_ == Mode::sandbox)
    for (auto& [dock, shown] : docks_) shown = dock->isVisible(), dock->hide();
  mode_ = m;
  pages_->setCurrentIndex(static_cast<int>(m));
  if (m == Mode::sandbox)
    for (auto& [dock, shown] : docks_) dock->setVisible(shown);
  for (QAction* a : sandbox_actions_) a->setEnabled(m == Mode::sandbox);
  for (QLabel* l : {status_time_, status_speed_, status_fps_, status_found_}) l->setVisible(m == Mode::sandbox);  // the sandbox's figures
  if (m != Mode::sandbox) status_inexact_->hide();
  mode_actions_[static_cast<std::size_t>(m)]->setChecked(true);
  static const char* const titles[] = {"salsa — sandbox", "salsa — queue", "salsa — map creator"};
  setWindowTitle(titles[static_cast<int>(m)]);
}

std::string MainWindow::open_test_spec(const TestSpec& test) {
  const TestSpec previous = file_base_;
  file_base_ = test;
  file_base_.changes.clear();
  if (const std::string why = load(file_base_); !why.empty()) {
    file_base_ = previous;
    return why;
  }
  set_mode(Mode::sandbox);
  if (!test.changes.empty())
    show_message(QString("'%1': its %2 timed changes are not replayed in the sandbox (salsa run replays them)").arg(q(test.name)).arg(test.changes.size()), false);
  return {};
}

void MainWindow::fill_plugin_lists() {
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

void MainWindow::use_plugins(std::shared_ptr<const PluginHost> host, const QStringList& rebuilt) {
  host_ = std::move(host);
  queue_->set_host(host_);
  fill_plugin_lists();
  const std::string running = engine_.behavior_name();
  std::string file;
  bool reload = false;
  if (!running.empty() && host_->behaviors().end() != std::find_if(host_->behaviors().begin(), host_->behaviors().end(),
                                                                    [&](const auto& e) { return e.factory.name == running; })) {
    file = host_->behavior(running).plugin().file.string();
    reload = rebuilt.contains(q(file));
  }
  pending_.push_back({engine_.use_plugins(host_, reload), [this, reload, running, file](const std::string& why) {
                        if (!why.empty()) return show_message(q("behavior '" + running + "' (" + file + ") was not reloaded: " + why));
                        if (!reload) return show_message(QString("plugins rescanned: %1 files").arg(host_->plugins().size()), false);
                        if (auto t = engine_.current_test()) {
                          loaded_ = *t;
                          show_test(*t);  // the new code's parameters
                        }
                        show_message(q("reloaded behavior '" + running + "' from " + file + ": the simulation goes on with the new code"), false);
                      }});
}

MainWindow::~MainWindow() {
  if (recorder_) recorder_->stop();
}

// ---------------------------------------------------------------- controls

void MainWindow::build_controls() {
  auto* panel = new QWidget;
  auto* column = new QVBoxLayout(panel);

  auto* setup = new QGroupBox("Test (changing these starts over)");
  auto* form = new QFormLayout(setup);
  behavior_ = new QComboBox;
  for (const auto& e : host_->behaviors()) behavior_->addItem(q(e.factory.name));
  behavior_->setToolTip("the behavior every drone runs");
  form->addRow("behavior", behavior_);
  map_ = new QComboBox;
  for (const auto& e : host_->maps())
    if (e.factory.name != "json") map_->addItem(q(e.factory.name));
  form->addRow("map", map_);
  map_panel_ = new ParamPanel;
  form->addRow(map_panel_);
  auto* file_row = new QHBoxLayout;
  map_file_label_ = new QLabel("(generated)");
  map_file_label_->setWordWrap(true);
  auto* open_map_button = new QPushButton("Map file…");
  open_map_button->setToolTip("use a JSON map file instead of a generated map");
  file_row->addWidget(map_file_label_, 1);
  file_row->addWidget(open_map_button);
  form->addRow(file_row);
  target_kind_ = new QComboBox;
  for (const auto& e : host_->target_kinds()) target_kind_->addItem(q(e.factory.name));
  form->addRow("target kind", target_kind_);
  targets_ = new QSpinBox;
  targets_->setRange(0, 10'000'000);
  targets_->setSingleStep(100);
  form->addRow("targets", targets_);
  seed_ = new QSpinBox;
  seed_->setRange(0, 2'000'000'000);
  form->addRow("seed", seed_);
  column->addWidget(setup);

  auto* live = new QGroupBox("Live (recorded; kept by Save as test)");
  auto* live_form = new QVBoxLayout(live);
  auto* drones_row = new QFormLayout;
  drones_ = new QSpinBox;
  drones_->setRange(1, 1'000'000);
  drones_->setKeyboardTracking(false);
  drones_->setToolTip("drones added at the spawn point, or the highest ids removed");
  drones_row->addRow("drones", drones_);
  live_form->addLayout(drones_row);
  live_form->addWidget(new QLabel("<b>Behavior parameters</b>"));
  behavior_panel_ = new ParamPanel;
  live_form->addWidget(behavior_panel_);
  auto* drone_row = new QHBoxLayout;
  drone_row->addWidget(new QLabel("<b>Drone</b>"));
  drone_config_ = new QComboBox;
  drone_config_->setToolTip("a named drone configuration: choosing one applies its values");
  drone_row->addWidget(drone_config_, 1);
  auto* save_config = new QPushButton("Save as…");
  save_config->setToolTip("save the values below as a named configuration");
  drone_row->addWidget(save_config);
  live_form->addLayout(drone_row);
  drone_panel_ = new ParamPanel;
  drone_panel_->set_schema(drone_schema());
  live_form->addWidget(drone_panel_);
  column->addWidget(live);

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
  pacing_->addItems({"real time", "steps per frame", "larger time step ×", "as fast as possible"});
  pacing_->setToolTip("real time; N exact steps per frame; a step N times longer (fast, inexact); or flat out");
  pacing_amount_ = new QSpinBox;
  pacing_amount_->setRange(1, 1000);
  pacing_amount_->setValue(4);
  pacing_amount_->setEnabled(false);
  speed->addWidget(pacing_, 1);
  speed->addWidget(pacing_amount_);
  run_layout->addLayout(speed);
  column->insertWidget(0, run);  // first: the buttons used most stay in sight
  column->addStretch();

  auto* scroll = new QScrollArea;
  scroll->setWidget(panel);
  scroll->setWidgetResizable(true);
  scroll->setMinimumWidth(340);
  auto* left = new QDockWidget("Sandbox");
  left->setObjectName("sandbox_dock");
  left->setWidget(scroll);
  left->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetFloatable);
  addDockWidget(Qt::LeftDockWidgetArea, left);

  charts_ = new LiveCharts;
  auto* plots = new QDockWidget("Live plots");
  plots->setObjectName("plots_dock");
  plots->setWidget(charts_);
  plots->setMinimumWidth(300);
  addDockWidget(Qt::RightDockWidgetArea, plots);
  inspector_ = new QPlainTextEdit;
  inspector_->setReadOnly(true);
  inspector_->setPlaceholderText("Click a drone to inspect it.");
  inspector_->setMaximumHeight(220);
  auto* inspect = new QDockWidget("Inspector");
  inspect->setObjectName("inspector_dock");
  inspect->setWidget(inspector_);
  addDockWidget(Qt::RightDockWidgetArea, inspect);
  for (QDockWidget* d : {left, plots, inspect}) docks_.emplace_back(d, true);

  status_time_ = new QLabel;
  status_speed_ = new QLabel;
  status_fps_ = new QLabel;
  status_found_ = new QLabel;
  status_inexact_ = new QLabel("inexact: larger time step");
  status_inexact_->setStyleSheet("color: #b00020; font-weight: bold");
  status_inexact_->hide();
  for (QLabel* l : {status_time_, status_speed_, status_fps_, status_found_, status_inexact_}) statusBar()->addPermanentWidget(l);

  // Start state: a new load. Live values: a recorded change.
  auto reload = [this] {
    if (!updating_) reload_from_controls();
  };
  // Another behavior or map starts from its own declared defaults.
  connect(behavior_, &QComboBox::currentTextChanged, this, [this](const QString& name) {
    if (updating_) return;
    const auto& e = host_->behavior(name.toStdString());
    behavior_panel_->set_schema(e.factory.parameters, ParameterValues(e.factory.parameters));
    reload_from_controls();
  });
  connect(map_, &QComboBox::currentTextChanged, this, [this](const QString& name) {
    if (updating_) return;
    map_file_.clear();
    const auto& e = host_->map(name.toStdString());
    map_panel_->set_schema(e.factory.parameters, ParameterValues(e.factory.parameters));
    reload_from_controls();
  });
  connect(map_panel_, &ParamPanel::changed, this, reload);
  connect(target_kind_, &QComboBox::currentTextChanged, this, reload);
  connect(targets_, &QSpinBox::valueChanged, this, reload);
  connect(seed_, &QSpinBox::valueChanged, this, reload);
  connect(open_map_button, &QPushButton::clicked, this, [this] {
    const QString file = QFileDialog::getOpenFileName(this, "Open a map", {}, "JSON maps (*.json)");
    if (!file.isEmpty()) open_map(file);
  });
  connect(drones_, &QSpinBox::valueChanged, this, [this](int n) {
    if (!updating_) live_change("drones", n);
  });
  connect(behavior_panel_, &ParamPanel::changed, this, [this](const std::string& name, double v) {
    if (!updating_) live_change("behavior.params." + name, v);
  });
  connect(drone_panel_, &ParamPanel::changed, this, [this](const std::string& name, double v) {
    if (!updating_) live_change("drone." + name, v);
  });
  connect(drone_config_, &QComboBox::activated, this, [this](int) { apply_drone_config(drone_config_->currentText()); });
  connect(save_config, &QPushButton::clicked, this, &MainWindow::save_drone_config);
  connect(run_button_, &QPushButton::clicked, this, &MainWindow::toggle_run);
  connect(step_button, &QPushButton::clicked, this, &MainWindow::step);
  connect(reset_button, &QPushButton::clicked, this, &MainWindow::reset);
  connect(pacing_, &QComboBox::currentIndexChanged, this, &MainWindow::set_pacing);
  connect(pacing_amount_, &QSpinBox::valueChanged, this, &MainWindow::set_pacing);
}

void MainWindow::build_menus() {
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("&Open test…", QKeySequence::Open, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Open a test", {}, "Tests (*.json)");
    if (!f.isEmpty()) open_test(f);
  });
  file->addAction("Open &map…", QKeySequence(Qt::CTRL | Qt::Key_M), this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Open a map", {}, "JSON maps (*.json)");
    if (!f.isEmpty()) open_map(f);
  });
  file->addAction("&Save as test…", QKeySequence::Save, this, [this] {
    const QString f = QFileDialog::getSaveFileName(this, "Save as test", "sandbox.json", "Tests (*.json)");
    if (!f.isEmpty()) save_test(f);
  });
  file->addSeparator();
  file->addAction("Screens&hot…", QKeySequence(Qt::CTRL | Qt::Key_P), this, [this] {
    const QString f = QFileDialog::getSaveFileName(this, "Screenshot", "salsa.png", "PNG images (*.png)");
    if (!f.isEmpty()) save_screenshot(f);
  });
  record_action_ = file->addAction("Start &recording…", QKeySequence(Qt::CTRL | Qt::Key_R), this, &MainWindow::toggle_recording);
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, this, &QWidget::close);

  QMenu* run = menuBar()->addMenu("&Run");
  sandbox_actions_.push_back(run->addAction("Start / pause", QKeySequence(Qt::Key_Space), this, &MainWindow::toggle_run));
  QAction* step_action = run->addAction("Step", this, &MainWindow::step);
  step_action->setShortcuts({QKeySequence(Qt::Key_Right), QKeySequence(Qt::Key_S)});
  sandbox_actions_.push_back(step_action);
  sandbox_actions_.push_back(run->addAction("Reset", QKeySequence(Qt::Key_R), this, &MainWindow::reset));

  QMenu* view = menuBar()->addMenu("&View");
  sandbox_actions_.push_back(view->addAction("Fit map", QKeySequence(Qt::Key_F), view_, &SwarmView::fit));
  sandbox_actions_.push_back(view->addAction("Zoom in", QKeySequence(Qt::Key_Plus), this, [this] { view_->zoom(1.25); }));
  sandbox_actions_.push_back(view->addAction("Zoom out", QKeySequence(Qt::Key_Minus), this, [this] { view_->zoom(0.8); }));
  view->addSeparator();
  struct Toggle {
    const char* text;
    bool ViewOptions::*flag;
  };
  for (const Toggle& t : {Toggle{"Camera range", &ViewOptions::camera_range}, Toggle{"Obstacle range", &ViewOptions::obstacle_range},
                          Toggle{"Detection range", &ViewOptions::detection_range}, Toggle{"Targets", &ViewOptions::targets},
                          Toggle{"Trails", &ViewOptions::trails}, Toggle{"Heat map", &ViewOptions::heat_map},
                          Toggle{"Obstacles", &ViewOptions::obstacles}, Toggle{"Spawn point", &ViewOptions::spawn}}) {
    QAction* a = view->addAction(t.text);
    a->setCheckable(true);
    a->setChecked(view_->options().*t.flag);
    a->setObjectName(QString("view_") + t.text);
    connect(a, &QAction::toggled, this, [this, flag = t.flag](bool on) {
      ViewOptions o = view_->options();
      o.*flag = on;
      view_->set_options(o);
    });
    view_toggles_.emplace_back(a, t.flag);
  }

  // Modes: a tool bar of three, Ctrl+1/2/3; each keeps its state while the others are shown.
  QToolBar* modes = addToolBar("Mode");
  modes->setObjectName("mode_toolbar");
  modes->setMovable(false);
  auto* group = new QActionGroup(this);
  const std::pair<const char*, Mode> mode_list[] = {{"Sandbox", Mode::sandbox}, {"Queue", Mode::queue}, {"Map creator", Mode::map_creator}};
  for (const auto& [text, m] : mode_list) {
    QAction* a = modes->addAction(text, this, [this, m = m] { set_mode(m); });
    a->setCheckable(true);
    a->setShortcut(QKeySequence(Qt::CTRL | static_cast<Qt::Key>(Qt::Key_1 + static_cast<int>(m))));
    a->setToolTip(QString("%1 (%2)").arg(text, a->shortcut().toString()));
    group->addAction(a);
    mode_actions_.push_back(a);
  }
  mode_actions_.front()->setChecked(true);

  QMenu* plugins = menuBar()->addMenu("&Plugins");
  plugins->addAction("&Plugins…", this, &MainWindow::show_plugins);
  plugins->addAction("&Rescan plugin folders", QKeySequence(Qt::Key_F5), plugins_, &PluginManager::rescan);
  QAction* auto_reload = plugins->addAction("Reload rebuilt plugins &automatically");
  auto_reload->setCheckable(true);
  auto_reload->setChecked(plugins_->watching());
  connect(auto_reload, &QAction::toggled, plugins_, &PluginManager::set_watching);

  QMenu* help = menuBar()->addMenu("&Help");
  help->addAction("&Keyboard shortcuts", QKeySequence::HelpContents, this, &MainWindow::show_shortcuts);
  help->addAction("&About salsa", this, [this] {
    QMessageBox::about(this, "About salsa",
                       QString("<b>salsa %1</b><p>A swarm algorithm simulator: behaviors, maps, targets and metrics are "
                               "plugins; this is its sandbox. Headless: <tt>salsa run</tt> or <tt>salsa-gui --headless</tt>.")
                           .arg(salsa_version()));
  });
}

void MainWindow::set_view_options(const ViewOptions& options) {
  for (auto& [action, flag] : view_toggles_) {
    const QSignalBlocker quiet(action);
    action->setChecked(options.*flag);
  }
  view_->set_options(options);
}

void MainWindow::show_shortcuts() {
  QString text = "<table>";
  for (const auto& s : shortcuts) text += QString("<tr><td><b>%1</b>&nbsp;&nbsp;</td><td>%2</td></tr>").arg(s[0], s[1]);
  text += "</table>";
  auto* box = new QMessageBox(QMessageBox::NoIcon, "Keyboard shortcuts", text, QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

void MainWindow::show_message(const QString& text, bool error) {
  last_message_ = text;
  statusBar()->showMessage(text, 10000);
  if (!error) return;
  // Not modal-blocking: the simulation and the view go on while the message is up.
  auto* box = new QMessageBox(QMessageBox::Warning, "salsa", text, QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

// ---------------------------------------------------------------- start states

std::optional<TestSpec> MainWindow::spec_from_controls(std::string* why) {
  // What the controls do not show (dt, log interval, spawn, metrics, ...) comes from the test opened
  // last; the rest from the controls. Parsed like a test file, so the CLI's checks and messages apply.
  json j = json::parse(resolved_json(file_base_, *host_));
  j.erase("versions");
  j.erase("changes");
  j["behavior"] = {{"name", behavior_->currentText().toStdString()}, {"params", params_json(behavior_panel_)}};
  DroneConfig d = loaded_ ? loaded_->drone : file_base_.drone;
  d.name = drone_config_->currentText().toStdString();
  for (const Parameter& p : drone_panel_->schema()) *drone_property(d, p.name) = drone_panel_->value(p.name);
  j["drone"] = drone_json(d);
  j["drones"] = drones_->value();
  if (!map_file_.isEmpty()) j["map"] = {{"file", map_file_.toStdString()}};
  else j["map"] = {{"name", map_->currentText().toStdString()}, {"params", params_json(map_panel_)}};
  const bool same_kind = target_kind_->currentText().toStdString() == file_base_.target.name;
  j["targets"] = {{"kind", target_kind_->currentText().toStdString()}, {"count", targets_->value()}};
  if (same_kind) j["targets"]["params"] = json::parse(resolved_json(file_base_, *host_))["targets"]["params"];
  j["seed"] = seed_->value();
  try {
    return parse_test(j.dump(), "sandbox", *host_);
  } catch (const std::exception& e) {
    if (why) *why = e.what();
    return std::nullopt;
  }
}

std::string MainWindow::load(const TestSpec& test) {
  const std::string why = engine_.load(test).get();  // building a world takes a moment; the user asked for it
  if (!why.empty()) {
    show_message(q(why));
    if (loaded_) show_test(*engine_.current_test());  // the controls go back to what runs
    return why;
  }
  loaded_ = test;
  show_test(test);
  view_->fit();
  return {};
}

void MainWindow::reload_from_controls() {
  std::string why;
  const auto spec = spec_from_controls(&why);
  if (!spec) {
    show_message(q(why));
    if (loaded_) show_test(*engine_.current_test());
    return;
  }
  load(*spec);
}

void MainWindow::show_test(const TestSpec& t) {
  const bool was = updating_;
  updating_ = true;
  behavior_->setCurrentText(q(t.behavior.name));
  behavior_panel_->set_schema(host_->behavior(t.behavior.name).factory.parameters, t.behavior.params);
  if (t.map.name == "json") {
    map_file_ = q(t.map_file);
    map_file_label_->setText(QFileInfo(map_file_).fileName());
    map_file_label_->setToolTip(map_file_);
    map_panel_->set_schema({});
  } else {
    map_file_.clear();
    map_file_label_->setText("(generated)");
    map_->setCurrentText(q(t.map.name));
    map_panel_->set_schema(host_->map(t.map.name).factory.parameters, t.map.params);
  }
  target_kind_->setCurrentText(q(t.target.name));
  targets_->setValue(static_cast<int>(t.targets));
  seed_->setValue(static_cast<int>(t.seed));
  drones_->setValue(static_cast<int>(t.drones));
  drone_config_->clear();
  for (const DroneConfig& c : drone_configs()) drone_config_->addItem(q(c.name));
  if (drone_config_->findText(q(t.drone.name)) < 0) drone_config_->addItem(q(t.drone.name));
  drone_config_->setCurrentText(q(t.drone.name));
  for (const Parameter& p : drone_panel_->schema()) drone_panel_->set_value(p.name, drone_value(t.drone, p.name));
  updating_ = was;
}

std::string MainWindow::open_test(const QString& file) {
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
    show_message(QString("%1: its %2 timed changes are not replayed in the sandbox (salsa run replays them)").arg(file).arg(tests.front().changes.size()), false);
  return {};
}

std::string MainWindow::open_map(const QString& file) {
  try {
    load_map_file(file.toStdString(), *host_, loaded_ ? loaded_->drone.radius : 1);  // the CLI's checks, before anything changes
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

std::string MainWindow::save_test(const QString& file) {
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

std::string MainWindow::save_screenshot(const QString& file) {
  QString error;
  if (!save_png(view_->screenshot(), file, &error)) {
    show_message(error);
    return error.toStdString();
  }
  show_message("saved " + file, false);
  return {};
}

// ---------------------------------------------------------------- live changes and running

void MainWindow::live_change(const std::string& key, double value) {
  pending_.push_back({engine_.set(key, value), [this](const std::string& why) {
                        if (why.empty()) return;
                        show_message(q(why));
                        if (auto t = engine_.current_test()) show_test(*t);  // back to what runs
                      }});
}

std::vector<DroneConfig> MainWindow::drone_configs() const {
  std::vector<DroneConfig> all = builtin_drone_configs();
  QSettings settings;
  const auto saved = settings.value("drone_configs").toString().toStdString();
  if (saved.empty()) return all;
  try {
    const json configs = json::parse(saved);  // named: items() of a temporary would dangle
    for (const auto& [name, v] : configs.items()) {
      DroneConfig d;
      d.name = name;
      for (const Parameter& p : drone_schema()) *drone_property(d, p.name) = v.value(p.name, *drone_property(d, p.name));
      d.obstacle_rays = v.value("obstacle_rays", d.obstacle_rays);
      all.push_back(d);
    }
  } catch (const std::exception&) {
    // A damaged settings entry: the built-in configurations still work.
  }
  return all;
}

void MainWindow::apply_drone_config(const QString& name) {
  for (const DroneConfig& c : drone_configs()) {
    if (q(c.name) != name) continue;
    // Each property a recorded change, as if set by hand (speed last: a larger radius may allow it).
    for (const char* field : {"radius", "camera_range", "obstacle_range", "detection_range", "max_force", "mass", "max_speed"})
      if (drone_panel_->value(field) != drone_value(c, field)) live_change(std::string("drone.") + field, drone_value(c, field));
    const bool was = updating_;
    updating_ = true;
    for (const Parameter& p : drone_panel_->schema()) drone_panel_->set_value(p.name, drone_value(c, p.name));
    updating_ = was;
    return;
  }
}

void MainWindow::save_drone_config() {
  bool ok = false;
  const QString name = QInputDialog::getText(this, "Save drone configuration", "Name:", QLineEdit::Normal, "my-drone", &ok);
  if (!ok || name.isEmpty()) return;
  if (const std::string why = name_problem(name.toStdString()); !why.empty()) {
    show_message("drone configuration name: " + q(why));
    return;
  }
  QSettings settings;
  json saved = json::object();
  try {
    const auto text = settings.value("drone_configs").toString().toStdString();
    if (!text.empty()) saved = json::parse(text);
  } catch (const std::exception&) {
  }
  json fields = params_json(drone_panel_);
  saved[name.toStdString()] = fields;
  settings.setValue("drone_configs", q(saved.dump()));
  const bool was = updating_;
  updating_ = true;
  if (drone_config_->findText(name) < 0) drone_config_->addItem(name);
  drone_config_->setCurrentText(name);
  updating_ = was;
  show_message("saved drone configuration '" + name + "'", false);
}

void MainWindow::start() {
  engine_.start();
  run_button_->setText("Pause");
}
void MainWindow::pause() {
  engine_.pause();
  run_button_->setText("Start");
}
void MainWindow::toggle_run() {
  const auto snap = engine_.snapshot();
  if (snap->state == RunState::running) pause();
  else start();
}
void MainWindow::step() {
  run_button_->setText("Start");
  pending_.push_back({engine_.step_once(), [this](const std::string& why) {
                        if (!why.empty()) show_message(q(why));
                      }});
}
void MainWindow::reset() {
  run_button_->setText("Start");
  pending_.push_back({engine_.reset(), [this](const std::string& why) {
                        if (!why.empty()) show_message(q(why));
                        else if (loaded_) show_test(*loaded_);
                      }});
}

void MainWindow::set_pacing() {
  Pacing p;
  const int mode = pacing_->currentIndex();
  p.mode = mode == 0 ? Pacing::real_time : mode == 1 ? Pacing::steps_per_frame : mode == 2 ? Pacing::real_time : Pacing::fastest;
  pacing_amount_->setEnabled(mode == 1 || mode == 2);
  if (mode == 1) p.steps = pacing_amount_->value();
  if (mode == 2) {  // the larger step runs as fast as it can: it is there for speed
    p.mode = Pacing::fastest;
    p.dt_factor = pacing_amount_->value();
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

void MainWindow::toggle_recording() {
  if (recorder_) {
    recorder_->stop();
    const int frames = recorder_->frames();
    QString error;
    const QString video = recorder_->make_video(&error);
    recorder_.reset();
    record_action_->setText("Start &recording…");
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
  record_action_->setText("Stop &recording");
  show_message(QString("recording a frame every %1 s of simulated time into %2").arg(interval).arg(folder), false);
}

// ---------------------------------------------------------------- showing

QString MainWindow::inspector_text() const { return inspector_->toPlainText(); }

void MainWindow::poll() {
  for (std::size_t i = 0; i < pending_.size();) {
    if (pending_[i].answer.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      ++i;
      continue;
    }
    Pending done = std::move(pending_[i]);
    pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(i));
    done.then(done.answer.get());
  }
}

void MainWindow::refresh() {
  poll();
  auto snap = engine_.snapshot();
  if (snap != shown_) {
    shown_ = snap;
    view_->show_snapshot(snap);
    ++frames_;
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
  status_time_->setText(QString("t = %1 s").arg(snap->time, 0, 'f', 1));
  status_speed_->setText(QString("%1× real time").arg(snap->speed, 0, 'f', snap->speed < 10 ? 2 : 0));
  status_fps_->setText(QString("%1 FPS").arg(fps_, 0, 'f', 0));
  const std::size_t targets = snap->found.size();
  status_found_->setText(targets ? QString("found %1 / %2 (%3 %)").arg(snap->targets_found).arg(targets)
                                       .arg(100.0 * static_cast<double>(snap->targets_found) / static_cast<double>(targets), 0, 'f', 1)
                                 : QString("no targets"));
  status_inexact_->setVisible(snap->inexact && mode_ == Mode::sandbox);
  if (snap->state == RunState::failed && snap->error != last_error_shown_) {
    last_error_shown_ = snap->error;
    run_button_->setText("Start");
    show_message(q(snap->error));
  }
  if (snap->state != RunState::running && run_button_->text() == "Pause") run_button_->setText("Start");
  if (snap->selected) {
    const Inspection& in = *snap->selected;
    QString text = QString("drone %1\nposition (%2, %3) m\nvelocity (%4, %5) m/s, speed %6 m/s\ncommanded (%7, %8) m/s\n")
                       .arg(in.id).arg(in.position.x, 0, 'f', 2).arg(in.position.y, 0, 'f', 2)
                       .arg(in.velocity.x, 0, 'f', 2).arg(in.velocity.y, 0, 'f', 2).arg(in.velocity.length(), 0, 'f', 2)
                       .arg(in.commanded.x, 0, 'f', 2).arg(in.commanded.y, 0, 'f', 2);
    text += QString("neighbours (%1 within %2 m):").arg(in.neighbours.size()).arg(snap->drone.detection_range);
    for (std::size_t i = 0; i < std::min<std::size_t>(in.neighbours.size(), 12); ++i) text += QString(" %1").arg(in.neighbours[i]);
    if (in.neighbours.size() > 12) text += " …";
    text += QString("\nobstacle hits: %1").arg(in.hits.size());
    for (const ObstacleHit& h : in.hits) text += QString(" %1 m").arg(h.distance, 0, 'f', 1);
    if (!in.memory.empty()) text += "\nmemory: " + q(in.memory);
    inspector_->setPlainText(text);
  } else if (!inspector_->toPlainText().isEmpty()) {
    inspector_->clear();
  }
}

// ---------------------------------------------------------------- settings

void MainWindow::restore_settings() {
  QSettings settings;
  restoreGeometry(settings.value("window/geometry").toByteArray());
  restoreState(settings.value("window/state").toByteArray());
  file_base_ = parse_test(first_test, "sandbox", *host_);
  // The last session's start state, if it still parses with the plugins there are now.
  const QString last = settings.value("sandbox/test").toString();
  if (!last.isEmpty()) {
    try {
      file_base_ = parse_test(last.toStdString(), "settings", *host_);
    } catch (const std::exception&) {
      // A plugin gone or a value out of range: the first scene instead.
    }
  }
  if (!load(file_base_).empty()) {
    file_base_ = parse_test(first_test, "sandbox", *host_);
    load(file_base_);
  }
}

void MainWindow::save_settings() {
  set_mode(Mode::sandbox);  // the window's layout is saved with the sandbox's docks where the user put them
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  settings.setValue("window/state", saveState());
  if (auto t = engine_.current_test()) {
    t->changes.clear();
    settings.setValue("sandbox/test", q(resolved_json(*t, *host_)));
  }
}

void MainWindow::closeEvent(QCloseEvent* event) {
  save_settings();
  QMainWindow::closeEvent(event);
}

}  // namespace salsa::gui
