#pragma once
// The main window. Three modes share it and keep their state when you switch (toolbar, Ctrl+1/2/3):
// the sandbox, queue mode (QueuePage) and the map creator (MapEditor). The sandbox window: the view in the middle, the set-up and live parameters on the left, live plots
// and the inspector on the right. Every control either changes the running simulation (behavior
// parameters, drone count, drone properties: recorded in the timeline) or loads a new start state
// (behavior, map, targets, seed). The window owns no simulation logic: it sends commands to the Engine
// and shows its snapshots.
#include <QMainWindow>
#include <QTimer>
#include <filesystem>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "engine.hpp"
#include "view.hpp"

class QComboBox;
class QSpinBox;
class QLabel;
class QPlainTextEdit;
class QPushButton;
class QAction;
class QStackedWidget;
class QDockWidget;

namespace salsa::gui {

class ParamPanel;
class LiveCharts;
class Recorder;
class PluginManager;
class QueuePage;
class MapEditor;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  /// `plugin_dirs`: the --plugin-dir folders `host` was loaded with (rescans and queue runs use them too).
  MainWindow(std::shared_ptr<const PluginHost> host, std::vector<std::filesystem::path> plugin_dirs, QWidget* parent = nullptr);
  /// Tests: `host` (not owned) was loaded from the default search path and outlives the window.
  explicit MainWindow(const PluginHost& host, QWidget* parent = nullptr);
  ~MainWindow() override;

  // ---- What the menus do, callable without dialogs (tests, command line). Each returns "" or the
  // one-line reason it was refused (also shown in a dialog); a refusal keeps the current state.
  enum class Mode { sandbox, queue, map_creator };
  void set_mode(Mode mode);
  Mode mode() const { return mode_; }

  std::string open_test(const QString& file);
  /// Loads `test` into the sandbox (queue mode's "Load into sandbox") and switches to it.
  std::string open_test_spec(const TestSpec& test);
  std::string open_map(const QString& file);
  /// The Plugins dialog: what loaded, what was refused and why, the folders searched; Rescan.
  void show_plugins();
  std::string save_test(const QString& file);
  std::string save_screenshot(const QString& file);
  void start();
  void pause();
  void toggle_run();
  void step();
  void reset();
  /// What the view shows (the View menu's toggles follow).
  void set_view_options(const ViewOptions& options);

  // ---- For tests ----
  Engine& engine() { return engine_; }
  SwarmView* view() const { return view_; }
  ParamPanel* behavior_panel() const { return behavior_panel_; }
  ParamPanel* drone_panel() const { return drone_panel_; }
  QSpinBox* drones_box() const { return drones_; }
  QComboBox* behavior_box() const { return behavior_; }
  LiveCharts* charts() const { return charts_; }
  const QString& last_message() const { return last_message_; }
  PluginManager* plugins() const { return plugins_; }
  QueuePage* queue_page() const { return queue_; }
  MapEditor* map_editor() const { return map_editor_; }
  std::shared_ptr<const PluginHost> host() const { return host_; }
  QString inspector_text() const;
  /// Applies every answer the engine has given so far (the timer does this 60 times a second).
  void poll();

 protected:
  void closeEvent(QCloseEvent*) override;

 private:
  void build_controls();
  void build_menus();
  /// The start state the controls describe (parsed like a test file, so the CLI's checks apply).
  std::optional<TestSpec> spec_from_controls(std::string* why);
  /// Loads `test` as the new start state; on refusal shows why and puts the controls back.
  std::string load(const TestSpec& test);
  /// Shows `test` in the controls, emitting nothing.
  void show_test(const TestSpec& test);
  void reload_from_controls();
  void live_change(const std::string& key, double value);
  void apply_drone_config(const QString& name);
  void save_drone_config();
  void set_pacing();
  void toggle_recording();
  void show_shortcuts();
  void show_message(const QString& text, bool error = true);
  /// A rescan's plugins: the lists follow; a rebuilt running behavior is switched to its new code.
  void use_plugins(std::shared_ptr<const PluginHost> host, const QStringList& rebuilt);
  void fill_plugin_lists();
  void refresh();  ///< 60 Hz: the latest snapshot to the view; status, charts and inspector a few times a second
  void restore_settings();
  void save_settings();
  std::vector<DroneConfig> drone_configs() const;  ///< built-in, then the user's saved ones

  std::shared_ptr<const PluginHost> host_;
  Engine engine_;
  std::shared_ptr<const PluginHost> editor_host_;  ///< the map creator reads maps with the plugins it started with
  PluginManager* plugins_ = nullptr;
  QStackedWidget* pages_ = nullptr;
  QueuePage* queue_ = nullptr;
  MapEditor* map_editor_ = nullptr;
  Mode mode_ = Mode::sandbox;
  std::vector<QAction*> mode_actions_;
  std::vector<QAction*> sandbox_actions_;  ///< shortcuts that act on the sandbox: off in the other modes
  std::vector<std::pair<QDockWidget*, bool>> docks_;  ///< the sandbox's docks, and whether each was shown
  SwarmView* view_ = nullptr;
  // Set-up controls.
  QComboBox* behavior_ = nullptr;
  QComboBox* map_ = nullptr;
  ParamPanel* map_panel_ = nullptr;
  QLabel* map_file_label_ = nullptr;
  QString map_file_;
  QComboBox* target_kind_ = nullptr;
  QSpinBox* targets_ = nullptr;
  QSpinBox* drones_ = nullptr;
  QSpinBox* seed_ = nullptr;
  ParamPanel* behavior_panel_ = nullptr;
  QComboBox* drone_config_ = nullptr;
  ParamPanel* drone_panel_ = nullptr;
  QPushButton* run_button_ = nullptr;
  QComboBox* pacing_ = nullptr;
  QSpinBox* pacing_amount_ = nullptr;
  LiveCharts* charts_ = nullptr;
  QPlainTextEdit* inspector_ = nullptr;
  QLabel* status_time_ = nullptr;
  QLabel* status_speed_ = nullptr;
  QLabel* status_fps_ = nullptr;
  QLabel* status_found_ = nullptr;
  QLabel* status_inexact_ = nullptr;
  QAction* record_action_ = nullptr;
  std::vector<std::pair<QAction*, bool ViewOptions::*>> view_toggles_;

  std::optional<TestSpec> loaded_;  ///< the start state running now
  TestSpec file_base_;              ///< what an opened test file set that the controls do not show
  bool updating_ = false;           ///< controls being set by the program: no commands
  struct Pending {
    std::future<std::string> answer;
    std::function<void(const std::string&)> then;
  };
  std::vector<Pending> pending_;
  QTimer timer_;
  std::shared_ptr<const Snapshot> shown_;
  int frames_ = 0;
  double fps_ = 0;
  std::chrono::steady_clock::time_point fps_since_, slow_refresh_;
  std::unique_ptr<Recorder> recorder_;
  QString last_message_;
  std::string last_error_shown_;
};

}  // namespace salsa::gui
