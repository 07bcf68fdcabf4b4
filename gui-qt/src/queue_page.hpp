#pragma once
// Queue mode: the table of tests (QueueModel) with add / sweep / edit / remove / reorder / save / load,
// and a run of the queue in the background. A run is `salsa run` of the saved queue file (the
// experiments layer, not a second implementation): its data equals the CLI's by construction; the page
// shows its progress and each test's status from the output folder.
#include <QWidget>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

#include "queue_model.hpp"
#include "sweep_dialog.hpp"

class QTableView;
class QProgressBar;
class QLabel;
class QPlainTextEdit;
class QPushButton;
class QCheckBox;
class QDialog;

namespace salsa::gui {

class NumberField;

class SalsaProcess;

class QueuePage : public QWidget {
  Q_OBJECT
 public:
  QueuePage(std::shared_ptr<const PluginHost> host, std::vector<std::filesystem::path> plugin_dirs, QWidget* parent = nullptr);
  ~QueuePage() override;
  void set_host(std::shared_ptr<const PluginHost> host);
  /// Where "Add from sandbox" and "Add sweep" take their test from.
  void set_sandbox(std::function<std::optional<TestSpec>(std::string*)> current) { sandbox_ = std::move(current); }
  /// Called by "Load into sandbox".
  void set_load_into_sandbox(std::function<void(const TestSpec&)> load) { load_into_sandbox_ = std::move(load); }
  /// The `salsa` program a run starts (default: the one beside this program).
  void set_salsa_program(QString program);
  /// salsa-gui --yes: queues over 10,000 tests are opened, swept and run (salsa run gets --yes).
  void set_allow_large(bool yes) { model_->set_allow_large(yes); }
  /// What Plots does with a finished test's plots folder and its PNGs (default: a dialog showing them).
  void set_plots_opener(std::function<void(const QString& folder, const QStringList& pngs)> open) { open_plots_ = std::move(open); }

  // ---- What the buttons do, callable without dialogs. "" or the one-line reason (also shown).
  std::string add_from_sandbox();
  std::string add_sweep(const SweepDialog& sweep);
  /// A queue file saved by Run (<out>.queue.json) beside its folder shows the results already there.
  std::string open(const QString& file);
  std::string save(const QString& file);
  /// Saves the queue beside `out` as <out>.queue.json and starts `salsa run` of it into `out`. A folder
  /// whose queue.json records this queue is resumed (--resume); one that records another queue is
  /// refused with salsa run's message, as salsa run refuses it.
  std::string run(const QString& out, const QStringList& extra_args = {});
  void stop();
  bool running() const;
  bool wait(int ms);  ///< waits for a run to end, handling events (tests)
  void show_plots(int row);
  void edit_json(int row);

  QueueModel* model() const { return model_; }
  QTableView* table() const { return table_; }
  QString output_dir() const { return out_; }
  QProgressBar* progress() const { return progress_; }
  QString log_text() const;
  const QString& last_message() const { return last_message_; }

 private:
  void update_statuses();
  /// A finished test's outcome in a few words, from its folder's outcome.csv ("" when unreadable).
  static std::string outcome_words(const QString& folder);
  void update_progress(int finished);
  void show_message(const QString& text, bool error = true);
  int selected_row() const;
  std::shared_ptr<const PluginHost> host_;
  std::vector<std::filesystem::path> plugin_dirs_;
  QueueModel* model_ = nullptr;
  QTableView* table_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* state_ = nullptr;
  QPlainTextEdit* log_ = nullptr;
  NumberField* jobs_ = nullptr;
  QCheckBox* plots_ = nullptr;
  QPushButton* run_button_ = nullptr;
  QPushButton* stop_button_ = nullptr;
  SalsaProcess* process_ = nullptr;
  QString out_;
  std::unordered_set<std::string> run_names_;  ///< the tests of the running (or last) run
  std::function<std::optional<TestSpec>(std::string*)> sandbox_;
  std::function<void(const TestSpec&)> load_into_sandbox_;
  std::function<void(const QString&, const QStringList&)> open_plots_;
  QString last_message_;
};

}  // namespace salsa::gui
