#include "main_window.hpp"

#include <QAction>
#include <QActionGroup>
#include <QCloseEvent>
#include <QDockWidget>
#include <QKeySequence>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QResizeEvent>
#include <QSettings>
#include <QSignalBlocker>
#include <QStackedWidget>
#include <QStatusBar>
#include <QTableWidget>
#include <QTimer>
#include <QToolBar>

#include "live_charts.hpp"
#include "map_editor.hpp"
#include "number_field.hpp"
#include "plugins.hpp"
#include "queue_page.hpp"
#include "replay_page.hpp"
#include "tune_page.hpp"

namespace salsa::gui {

class ElidedLabel : public QLabel {
 public:
  ElidedLabel() {
    setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);  // never widens the bar over its neighbours
    setMinimumWidth(40);
    clear_.setSingleShot(true);
    connect(&clear_, &QTimer::timeout, this, [this] { set_full({}); });
  }
  void set_full(const QString& text) {
    full_ = text;
    setToolTip(text);
    elide();
    if (!text.isEmpty()) clear_.start(15000);
  }
  const QString& full() const { return full_; }

 protected:
  void resizeEvent(QResizeEvent* e) override {
    QLabel::resizeEvent(e);
    elide();
  }

 private:
  void elide() { setText(fontMetrics().elidedText(full_, Qt::ElideRight, std::max(0, width() - 4))); }
  QString full_;
  QTimer clear_;
};

namespace {

const char* const shortcuts[][2] = {
    {"Space", "start / pause (the view focused: click it)"}, {"Right, S", "one step (the view focused)"},
    {"R", "reset to the start state, asked first once the run has begun (the view focused)"},
    {"+ / −, wheel", "zoom"},         {"0, F", "fit the map"},          {"drag", "pan"},
    {"click a drone", "inspect it"},  {"Ctrl+O", "open a test"},        {"Ctrl+M", "open a map"},
    {"Ctrl+S", "save as test"},       {"Ctrl+P", "screenshot"},         {"Ctrl+R", "start / stop recording"},
    {"Ctrl+Shift+O", "open results (replay)"},
    {"Space, Left / Right", "replay: play / pause, frame back / on (the replay page focused)"},
    {"Ctrl+1 / 2 / 3 / 4 / 5", "sandbox / queue / map creator / tune / replay"}, {"F5", "rescan plugin folders"},
    {"V L P O S B", "map creator: select, line, polygon, hollow, spawn, bounds"},
    {"Ctrl+Z / Ctrl+Shift+Z", "map creator: undo / redo"}, {"Delete / Esc", "map creator: delete the selection / drop the polygon being drawn"},
    {"Ctrl+Q", "quit"},
};

}  // namespace

MainWindow::MainWindow(std::shared_ptr<const PluginHost> host, std::vector<std::filesystem::path> plugin_dirs, QWidget* parent)
    : QMainWindow(parent), host_(host), editor_host_(host) {
  setWindowTitle("salsa — sandbox");
  plugins_ = new PluginManager(plugin_dirs, host_, this);
  connect(plugins_, &PluginManager::plugins_changed, this,
          [this](std::shared_ptr<const PluginHost> h, const QStringList& rebuilt) { use_plugins(std::move(h), rebuilt); });
  // In the status bar, not a dialog: a build still writing the file causes these, and the next write retries.
  connect(plugins_, &PluginManager::reload_failed, this, [this](const QString& why) { show_status(why, false); });
  sandbox_ = new SandboxPage(host_);
  connect(sandbox_, &SandboxPage::message, this, &MainWindow::show_status);
  connect(static_cast<NumberRefusals*>(NumberField::refusals()), &NumberRefusals::refused, this,
          [this](const QString& why) { show_status(why, true); });
  queue_ = new QueuePage(host_, plugin_dirs);
  auto sandbox_test = [this](std::string* why) -> std::optional<TestSpec> {
    auto t = sandbox_->engine().current_test();
    if (!t && why) *why = "no test loaded in the sandbox";
    return t;
  };
  auto load_into_sandbox = [this](const TestSpec& t) {
    if (sandbox_->open_test_spec(t).empty()) set_mode(Mode::sandbox);
  };
  queue_->set_sandbox(sandbox_test);
  queue_->set_load_into_sandbox(load_into_sandbox);
  tune_ = new TunePage(host_, plugin_dirs);
  tune_->set_sandbox(sandbox_test);
  tune_->set_load_into_sandbox(load_into_sandbox);
  map_editor_ = new MapEditor(*editor_host_);
  connect(map_editor_, &MapEditor::map_saved, this, [this](const QString& file) {
    show_status("saved " + file + ": \"Map file…\" in the sandbox, or a test's \"map\": {\"file\": ...}, uses it", false);
  });
  connect(map_editor_, &MapEditor::use_in_sandbox, this, [this](const QString& file) {
    if (sandbox_->open_map(file).empty()) set_mode(Mode::sandbox);
  });
  replay_ = new ReplayPage;
  connect(replay_, &ReplayPage::message, this, &MainWindow::show_status);
  pages_ = new QStackedWidget;
  pages_->addWidget(sandbox_);
  pages_->addWidget(queue_);
  pages_->addWidget(map_editor_);
  pages_->addWidget(tune_);
  pages_->addWidget(replay_);
  for (int i = 1; i < pages_->count(); ++i) pages_->widget(i)->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored);
  setCentralWidget(pages_);
  build_docks();
  build_menus();
  restore_settings();
  replay_->set_view_options(sandbox_->view()->options());
}

MainWindow::MainWindow(const PluginHost& host, QWidget* parent)
    : MainWindow(std::shared_ptr<const PluginHost>(&host, [](const PluginHost*) {}), {}, parent) {}

MainWindow::~MainWindow() = default;

void MainWindow::build_docks() {
  auto* left = new QDockWidget("Sandbox");
  left->setObjectName("sandbox_dock");
  left->setWidget(sandbox_->controls());
  left->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetFloatable);
  addDockWidget(Qt::LeftDockWidgetArea, left);
  auto* plots = new QDockWidget("Live plots");
  plots->setObjectName("plots_dock");
  plots->setWidget(sandbox_->charts());
  plots->setMinimumWidth(300);
  addDockWidget(Qt::RightDockWidgetArea, plots);
  auto* inspect = new QDockWidget("Inspector");
  inspect->setObjectName("inspector_dock");
  inspect->setWidget(sandbox_->inspector());
  addDockWidget(Qt::RightDockWidgetArea, inspect);
  for (QDockWidget* d : {left, plots, inspect}) docks_.emplace_back(d, true);
  // The message takes what the figures leave, elided: a long one never runs into them.
  status_ = new ElidedLabel;
  status_->setObjectName("status_line");
  statusBar()->addWidget(status_, 1);
  for (QLabel* l : sandbox_->status_labels()) statusBar()->addPermanentWidget(l);
}

QString MainWindow::status_text() const { return status_->full(); }
QLabel* MainWindow::status_line() const { return status_; }

void MainWindow::show_status(const QString& text, bool) { status_->set_full(text); }

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
  // Only the page shown sets the window's minimum size (the tune page's is not the sandbox's).
  for (int i = 0; i < pages_->count(); ++i)
    pages_->widget(i)->setSizePolicy(i == static_cast<int>(m) ? QSizePolicy(QSizePolicy::Preferred, QSizePolicy::Preferred)
                                                              : QSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored));
  if (m == Mode::sandbox)
    for (auto& [dock, shown] : docks_) dock->setVisible(shown);
  for (QAction* a : sandbox_actions_) a->setEnabled(m == Mode::sandbox);
  sandbox_->set_active(m == Mode::sandbox);  // the sandbox's figures
  mode_actions_[static_cast<std::size_t>(m)]->setChecked(true);
  static const char* const titles[] = {"salsa — sandbox", "salsa — queue", "salsa — map creator", "salsa — tune", "salsa — replay"};
  // Tune mode starts from the sandbox's test the first time it is shown.
  if (m == Mode::tune && tune_->parameters()->rowCount() == 0) tune_->from_sandbox();
  setWindowTitle(titles[static_cast<int>(m)]);
}

void MainWindow::use_plugins(std::shared_ptr<const PluginHost> host, const QStringList& rebuilt) {
  host_ = std::move(host);
  queue_->set_host(host_);
  tune_->set_host(host_);
  sandbox_->use_plugins(host_, rebuilt);
}

// ---------------------------------------------------------------- menus

void MainWindow::build_menus() {
  QMenu* file = menuBar()->addMenu("&File");
  // The sandbox's files: opening one switches to the sandbox.
  auto to_sandbox = [this](void (SandboxPage::*act)()) {
    return [this, act] {
      set_mode(Mode::sandbox);
      (sandbox_->*act)();
    };
  };
  file->addAction("&Open test…", QKeySequence::Open, this, to_sandbox(&SandboxPage::ask_open_test));
  file->addAction("Open &map…", QKeySequence(Qt::CTRL | Qt::Key_M), this, to_sandbox(&SandboxPage::ask_open_map));
  file->addAction("&Save as test…", QKeySequence::Save, this, to_sandbox(&SandboxPage::ask_save_test));
  // Replay: a finished test's folder played back (docs/replay.md); opening one switches to replay.
  file->addAction("Open &results…", QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_O), this, [this] {
    set_mode(Mode::replay);
    replay_->ask_open();
  });
  file->addAction("&Compare with…", this, [this] {
    set_mode(Mode::replay);
    replay_->ask_compare();
  });
  file->addSeparator();
  file->addAction("Screens&hot…", QKeySequence(Qt::CTRL | Qt::Key_P), this, to_sandbox(&SandboxPage::ask_screenshot));
  record_action_ = file->addAction("Start &recording…", QKeySequence(Qt::CTRL | Qt::Key_R), sandbox_, &SandboxPage::toggle_recording);
  connect(sandbox_, &SandboxPage::recording_changed, this,
          [this](bool on) { record_action_->setText(on ? "Stop &recording" : "Start &recording…"); });
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, this, &QWidget::close);

  // Single keys (Space, Right, S, R, F, +, -) act on the view: only while it has the focus (click it),
  // so a key typed into a field, slider or list, or onto a disabled one, never runs, steps or resets.
  auto view_key = [this](QAction* a) {
    a->setShortcutContext(Qt::WidgetShortcut);
    sandbox_->view()->addAction(a);
    sandbox_actions_.push_back(a);
    return a;
  };
  QMenu* run = menuBar()->addMenu("&Run");
  view_key(run->addAction("Start / pause", QKeySequence(Qt::Key_Space), sandbox_, &SandboxPage::toggle_run));
  QAction* step_action = view_key(run->addAction("Step", sandbox_, &SandboxPage::step));
  step_action->setShortcuts({QKeySequence(Qt::Key_Right), QKeySequence(Qt::Key_S)});
  view_key(run->addAction("Reset…", QKeySequence(Qt::Key_R), this, &MainWindow::ask_reset));

  QMenu* view = menuBar()->addMenu("&View");
  view_key(view->addAction("Fit map", QKeySequence(Qt::Key_F), sandbox_->view(), &SwarmView::fit));
  view_key(view->addAction("Zoom in", QKeySequence(Qt::Key_Plus), this, [this] { sandbox_->view()->zoom(1.25); }));
  view_key(view->addAction("Zoom out", QKeySequence(Qt::Key_Minus), this, [this] { sandbox_->view()->zoom(0.8); }));
  view->addSeparator();
  struct Toggle {
    const char* text;
    bool ViewOptions::*flag;
  };
  for (const Toggle& t : {Toggle{"Camera range", &ViewOptions::camera_range}, Toggle{"Obstacle range", &ViewOptions::obstacle_range},
                          Toggle{"Detection range", &ViewOptions::detection_range}, Toggle{"Targets", &ViewOptions::targets},
                          Toggle{"Trails", &ViewOptions::trails}, Toggle{"Heat map", &ViewOptions::heat_map},
                          Toggle{"Obstacles", &ViewOptions::obstacles}, Toggle{"Spawn point", &ViewOptions::spawn},
                          Toggle{"Communication links", &ViewOptions::links}, Toggle{"Wind", &ViewOptions::wind}}) {
    QAction* a = view->addAction(t.text);
    a->setCheckable(true);
    a->setChecked(sandbox_->view()->options().*t.flag);
    a->setObjectName(QString("view_") + t.text);
    connect(a, &QAction::toggled, this, [this, flag = t.flag](bool on) {
      ViewOptions o = sandbox_->view()->options();
      o.*flag = on;
      sandbox_->view()->set_options(o);
      replay_->set_view_options(o);
    });
    view_toggles_.emplace_back(a, t.flag);
  }

  // Modes: a tool bar of five, Ctrl+1…5; each keeps its state while the others are shown.
  QToolBar* modes = addToolBar("Mode");
  modes->setObjectName("mode_toolbar");
  modes->setMovable(false);
  auto* group = new QActionGroup(this);
  const std::pair<const char*, Mode> mode_list[] = {{"Sandbox", Mode::sandbox}, {"Queue", Mode::queue}, {"Map creator", Mode::map_creator}, {"Tune", Mode::tune}, {"Replay", Mode::replay}};
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

void MainWindow::ask_reset() {
  // A run that has gone some way is not thrown away by one key: asked first.
  const auto snap = sandbox_->engine().snapshot();
  if (snap && snap->time > 0) {
    const auto answer = QMessageBox::question(
        this, "Reset", QString("Reset to the start state? The run so far (t = %1 s) and its live changes are dropped.").arg(snap->time, 0, 'f', 1),
        QMessageBox::Reset | QMessageBox::Cancel, QMessageBox::Cancel);
    if (answer != QMessageBox::Reset) return;
  }
  sandbox_->reset();
}

void MainWindow::set_view_options(const ViewOptions& options) {
  for (auto& [action, flag] : view_toggles_) {
    const QSignalBlocker quiet(action);
    action->setChecked(options.*flag);
  }
  sandbox_->view()->set_options(options);
  replay_->set_view_options(options);
}

void MainWindow::show_shortcuts() {
  QString text = "<table>";
  for (const auto& s : shortcuts) text += QString("<tr><td><b>%1</b>&nbsp;&nbsp;</td><td>%2</td></tr>").arg(s[0], s[1]);
  text += "</table>";
  auto* box = new QMessageBox(QMessageBox::NoIcon, "Keyboard shortcuts", text, QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

// ---------------------------------------------------------------- settings

void MainWindow::restore_settings() {
  QSettings settings;
  restoreGeometry(settings.value("window/geometry").toByteArray());
  restoreState(settings.value("window/state").toByteArray());
  sandbox_->restore_settings();
}

void MainWindow::save_settings() {
  set_mode(Mode::sandbox);  // the window's layout is saved with the sandbox's docks where the user put them
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  settings.setValue("window/state", saveState());
  sandbox_->save_settings();
}

void MainWindow::closeEvent(QCloseEvent* event) {
  save_settings();
  QMainWindow::closeEvent(event);
}

}  // namespace salsa::gui
