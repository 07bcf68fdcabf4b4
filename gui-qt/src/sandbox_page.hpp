#pragma once
// The sandbox page: the view in the middle, the set-up and live parameters (a panel the window docks
// on the left), live plots and the inspector (docked on the right), and its figures for the status bar.
// Every control either changes the running simulation (behavior parameters, drone count, drone
// properties, the numbers of the test's models: recorded in the timeline) or loads a new start state
// (behavior, map, targets, seed, a model switched on or off). With two or more groups of drones, a group box chooses whose behavior, count and drone the
// controls show and change. The page owns no simulation logic: it sends commands to the Engine and
// shows its snapshots.
#include <QTimer>
#include <QWidget>
#include <array>
#include <chrono>
#include <filesystem>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "engine.hpp"
#include "view.hpp"

class QComboBox;
class QGroupBox;
class QToolButton;
class QLabel;
class QLineEdit;
class QPlainTextEdit;
class QPushButton;
class QVBoxLayout;

namespace salsa::gui {

class ParamPanel;
class NumberField;
class LiveCharts;
class Recorder;


class SandboxPage : public QWidget {
  Q_OBJECT
 public:
  explicit SandboxPage(std::shared_ptr<const PluginHost> host, QWidget* parent = nullptr);
  ~SandboxPage() override;

  // ---- What the menus do, callable without dialogs (tests, command line). Each returns "" or the
  // one-line reason it was refused (also shown); a refusal keeps the current state.
  std::string open_test(const QString& file);
  /// Loads `test` (queue mode's "Load into sandbox"): its seed, map file and all.
  std::string open_test_spec(const TestSpec& test);
  std::string open_map(const QString& file);
  std::string save_test(const QString& file);
  std::string save_screenshot(const QString& file);
  /// Saves the drone values shown as the named configuration (Save as… without its dialog); refused
  /// for a bad name or a built-in configuration's.
  std::string save_drone_config_as(const QString& name);
  void start();
  void pause();
  void toggle_run();
  void step();
  void reset();
  void toggle_recording();
  // The same with their file dialogs. A save that cannot succeed is refused before the dialog opens.
  void ask_open_test();
  void ask_open_map();
  void ask_save_test();
  void ask_screenshot();
  /// A rescan's plugins: the lists follow; a rebuilt running behavior is switched to its new code.
  void use_plugins(std::shared_ptr<const PluginHost> host, const QStringList& rebuilt);
  /// The last session's start state (or the first scene, saying why the last one could not be used).
  void restore_settings();
  void save_settings();
  /// Whether the page is the one shown (its status figures follow).
  void set_active(bool active);

  // ---- Parts the window places: the left dock, the right docks, the status bar's figures.
  QWidget* controls() const { return controls_; }
  LiveCharts* charts() const { return charts_; }
  QPlainTextEdit* inspector() const { return inspector_; }
  std::vector<QLabel*> status_labels() const;

  // ---- For tests ----
  Engine& engine() { return engine_; }
  SwarmView* view() const { return view_; }
  ParamPanel* behavior_panel() const { return behavior_panel_; }
  QComboBox* drone_config_box() const { return drone_config_; }  ///< named drone configurations: choosing one applies it
  ParamPanel* drone_panel() const { return drone_panel_; }
  ParamPanel* battery_panel() const { return battery_panel_; }   ///< the energy model's drone properties
  QToolButton* battery_toggle() const { return battery_toggle_; }  ///< shows or hides the battery panel
  ParamPanel* noise_panel() const { return noise_panel_; }       ///< the sensor noise drone properties
  QToolButton* noise_toggle() const { return noise_toggle_; }    ///< shows or hides the noise panel
  QComboBox* group_box() const { return group_; }                ///< whose controls (shown with 2+ groups)
  /// The box of a model of the test's sections (test_models(): "failures", "comm", "wind", any added),
  /// or nullptr. Checkable when the section alone switches the model on (a new start state).
  QGroupBox* model_box(const std::string& key) const;
  ParamPanel* model_panel(const std::string& key) const;  ///< its fields, live
  QPushButton* fail_button() const { return fail_; }             ///< fails the inspected drone (in the failures box)
  QLabel* comm_note() const { return comm_note_; }               ///< messages in flight, or why the view draws no links
  ParamPanel* map_panel() const { return map_panel_; }
  NumberField* drones_box() const { return drones_; }
  NumberField* targets_box() const { return targets_; }
  QLineEdit* seed_box() const { return seed_; }
  QComboBox* physics_box() const { return physics_; }             ///< box2d or light (a new start state)
  QComboBox* behavior_box() const { return behavior_; }
  QComboBox* map_box() const { return map_; }
  QLabel* time_label() const { return status_time_; }
  const QString& last_message() const { return last_message_; }
  QString inspector_text() const;
  /// Applies every answer the engine has given so far and a start-state edit still waiting, and shows
  /// the values a timed change set (the timer does this 60 times a second).
  void poll();

 Q_SIGNALS:
  /// For the window's status line (errors are also shown in a dialog by the page).
  void message(const QString& text, bool error);
  /// A recording started (true) or stopped: the window's menu follows.
  void recording_changed(bool on);

 private:
  void build_controls();  ///< the left dock (run controls, then the forms), the right docks' parts, the status figures

  // ---- The forms (sandbox_forms.cpp): the controls that show, build and read the test's settings.
  void build_forms(QVBoxLayout* column);
  /// The start state the controls describe (parsed like a test file, so the CLI's checks apply).
  std::optional<TestSpec> spec_from_controls(std::string* why);
  /// Shows `test` in the controls, emitting nothing. Panels of the same schema are updated in place.
  void show_test(const TestSpec& test);
  /// Shows `d` in the drone panels (the caller holds updating_).
  void show_drone(const DroneConfig& d);
  /// A start-state control changed: reloads once control returns to the event loop. Never at once: the
  /// reload rebuilds controls, and the one that asked may still be handling its key or focus event.
  void schedule_reload();
  void reload_from_controls();
  void seed_edited();
  /// `rest` ("drones", "drone.radius", "behavior.params.k") as the chosen group's key: plain with one
  /// group (saved tests stay in the single form), "groups.<name>.<rest>" with more.
  std::string group_key(const std::string& rest) const;
  /// The chosen group's index in `t` (0 when its name is not there).
  std::size_t chosen_group(const TestSpec& t) const;
  void apply_drone_config(const QString& name);

  // ---- The models' boxes (sandbox_models.cpp): one per model of test_models() with fields, from its
  // declaration (title, fields, ranges); values read and written through the fields' get and set.
  void build_model_boxes(QVBoxLayout* column);
  /// Shows the models of `t` (the caller holds updating_).
  void show_models(const TestSpec& t);
  /// The models' sections in `j` as the boxes say: a model that is off has none (its test keeps its bytes).
  void models_json(nlohmann::ordered_json& j) const;
  void save_drone_config();
  std::vector<DroneConfig> drone_configs() const;  ///< built-in, then the user's saved ones

  // ---- The page (sandbox_page.cpp)
  /// Loads `test` as the new start state; on refusal shows why and puts the controls back.
  std::string load(const TestSpec& test);
  /// A recorded change of the running test (keys as in changes.hpp); refused, the controls show what runs.
  void live_change(const std::string& key, double value);
  void set_pacing();
  void show_message(const QString& text, bool error = true);
  void fill_plugin_lists();
  void refresh();  ///< 60 Hz: the latest snapshot to the view; status, charts and inspector a few times a second

  std::shared_ptr<const PluginHost> host_;
  Engine engine_;
  SwarmView* view_ = nullptr;
  QWidget* controls_ = nullptr;
  // Set-up controls.
  QComboBox* behavior_ = nullptr;
  QComboBox* map_ = nullptr;
  ParamPanel* map_panel_ = nullptr;
  QLabel* map_file_label_ = nullptr;
  QString map_file_;
  QComboBox* target_kind_ = nullptr;
  NumberField* targets_ = nullptr;
  QLineEdit* seed_ = nullptr;
  QComboBox* physics_ = nullptr;
  QWidget* group_row_ = nullptr;
  QComboBox* group_ = nullptr;
  std::string group_name_;  ///< the chosen group
  NumberField* drones_ = nullptr;
  ParamPanel* behavior_panel_ = nullptr;
  QComboBox* drone_config_ = nullptr;
  ParamPanel* drone_panel_ = nullptr;
  QToolButton* battery_toggle_ = nullptr;
  ParamPanel* battery_panel_ = nullptr;
  QToolButton* noise_toggle_ = nullptr;
  ParamPanel* noise_panel_ = nullptr;
  /// The panels of the drone properties, one per section of drone_schema(), indexed by DroneSection.
  std::array<ParamPanel*, 3> drone_panels() const { return {drone_panel_, battery_panel_, noise_panel_}; }
  /// One per model of the test's sections with fields to edit, in test_models() order.
  struct ModelBox {
    std::string key;
    QGroupBox* box = nullptr;
    ParamPanel* panel = nullptr;
  };
  std::vector<ModelBox> model_boxes_;
  QPushButton* fail_ = nullptr;
  QLabel* comm_note_ = nullptr;  ///< the messages in flight, or why there are none
  std::optional<std::uint32_t> fail_target_;  ///< the inspected drone the fail button names
  QPushButton* run_button_ = nullptr;
  QComboBox* pacing_ = nullptr;
  NumberField* pacing_amount_ = nullptr;
  LiveCharts* charts_ = nullptr;
  QPlainTextEdit* inspector_ = nullptr;
  QLabel* status_time_ = nullptr;
  QLabel* status_speed_ = nullptr;
  QLabel* status_fps_ = nullptr;
  QLabel* status_found_ = nullptr;
  QLabel* status_inexact_ = nullptr;
  bool active_ = true;

  std::optional<TestSpec> loaded_;  ///< the start state running now
  TestSpec file_base_;              ///< what an opened test file set that the controls do not show
  std::uint64_t seed_value_ = 1;    ///< the seed the controls describe (the box holds its text)
  bool updating_ = false;           ///< controls being set by the program: no commands
  bool reload_due_ = false;         ///< a start-state edit waits for the event loop
  /// The loaded test's time was reached: paused once with a message; a Start after it runs on, said
  /// in the status bar.
  bool past_time_told_ = false;
  struct Pending {
    std::future<std::string> answer;
    std::function<void(const std::string&)> then;
  };
  std::vector<Pending> pending_;
  QTimer timer_;
  std::shared_ptr<const Snapshot> shown_;
  std::size_t changes_shown_ = 0;  // the snapshot's changes_applied the controls show
  int frames_ = 0;
  double fps_ = 0;
  std::chrono::steady_clock::time_point fps_since_, slow_refresh_;
  std::unique_ptr<Recorder> recorder_;
  QString last_message_;
  std::string last_error_shown_;
};

}  // namespace salsa::gui
