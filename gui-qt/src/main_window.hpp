#pragma once
// The main window: the shell around five pages that keep their state when you switch (toolbar,
// Ctrl+1…5): the sandbox (SandboxPage), queue mode (QueuePage), the map creator (MapEditor), tune
// mode (TunePage) and replay (ReplayPage). It
// owns the menus, the mode switch, the docks the sandbox's panels sit in, the status bar and the
// plugin manager; what each page does is in the page.
#include <QMainWindow>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "sandbox_page.hpp"

class QAction;
class QLabel;
class QStackedWidget;
class QDockWidget;

namespace salsa::gui {

class PluginManager;
class QueuePage;
class MapEditor;
class TunePage;
class ReplayPage;

/// A one-line label that elides what does not fit (the full text in its tooltip), so a long message
/// never runs into the figures beside it.
class ElidedLabel;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  /// `plugin_dirs`: the --plugin-dir folders `host` was loaded with (rescans and queue runs use them too).
  MainWindow(std::shared_ptr<const PluginHost> host, std::vector<std::filesystem::path> plugin_dirs, QWidget* parent = nullptr);
  /// Tests: `host` (not owned) was loaded from the default search path and outlives the window.
  explicit MainWindow(const PluginHost& host, QWidget* parent = nullptr);
  ~MainWindow() override;

  enum class Mode { sandbox, queue, map_creator, tune, replay };
  void set_mode(Mode mode);
  Mode mode() const { return mode_; }

  /// The Plugins dialog: what loaded, what was refused and why, the folders searched; Rescan.
  void show_plugins();
  /// What the view shows (the View menu's toggles follow).
  void set_view_options(const ViewOptions& options);
  /// Run > Reset (R on the view): asks first once the run has begun.
  void ask_reset();

  SandboxPage* sandbox() const { return sandbox_; }
  QueuePage* queue_page() const { return queue_; }
  MapEditor* map_editor() const { return map_editor_; }
  TunePage* tune_page() const { return tune_; }
  ReplayPage* replay_page() const { return replay_; }
  PluginManager* plugins() const { return plugins_; }
  std::shared_ptr<const PluginHost> host() const { return host_; }
  /// The status line's full text (shown elided).
  QString status_text() const;
  QLabel* status_line() const;

 protected:
  void closeEvent(QCloseEvent*) override;

 private:
  void build_docks();
  void build_menus();
  void show_shortcuts();
  void show_status(const QString& text, bool error);
  void use_plugins(std::shared_ptr<const PluginHost> host, const QStringList& rebuilt);
  void restore_settings();
  void save_settings();

  std::shared_ptr<const PluginHost> host_;
  std::shared_ptr<const PluginHost> editor_host_;  ///< the map creator reads maps with the plugins it started with
  PluginManager* plugins_ = nullptr;
  QStackedWidget* pages_ = nullptr;
  SandboxPage* sandbox_ = nullptr;
  QueuePage* queue_ = nullptr;
  MapEditor* map_editor_ = nullptr;
  TunePage* tune_ = nullptr;
  ReplayPage* replay_ = nullptr;
  ElidedLabel* status_ = nullptr;
  Mode mode_ = Mode::sandbox;
  std::vector<QAction*> mode_actions_;
  std::vector<QAction*> sandbox_actions_;  ///< shortcuts that act on the sandbox: off in the other modes
  std::vector<std::pair<QDockWidget*, bool>> docks_;  ///< the sandbox's docks, and whether each was shown
  QAction* record_action_ = nullptr;
  std::vector<std::pair<QAction*, bool ViewOptions::*>> view_toggles_;
};

}  // namespace salsa::gui
