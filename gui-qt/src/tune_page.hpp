#pragma once
// Tune mode: a tune file built from the sandbox's test (the numbers to tune ticked in a table, their
// ranges from the declarations, the objective, the algorithm and the budget), run as `salsa tune` in
// the background (the CLI's tuner, not a second one: its results equal the CLI's by construction), a
// live convergence chart read from the tune.csv and candidates.csv it rewrites after every generation,
// and the winner loaded into the sandbox.
#include <QWidget>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/experiments/tune_file.hpp"

class QCheckBox;
class QComboBox;
class QLabel;
class QLineEdit;
class QPlainTextEdit;
class QProgressBar;
class QPushButton;
class QTableWidget;
class QLineSeries;
class QScatterSeries;
class QValueAxis;
class QChartView;

namespace salsa::gui {

class NumberField;

class SalsaProcess;

class TunePage : public QWidget {
  Q_OBJECT
 public:
  TunePage(std::shared_ptr<const PluginHost> host, std::vector<std::filesystem::path> plugin_dirs, QWidget* parent = nullptr);
  ~TunePage() override;
  void set_host(std::shared_ptr<const PluginHost> host) { host_ = std::move(host); }
  /// Where "From sandbox" takes its test from.
  void set_sandbox(std::function<std::optional<TestSpec>(std::string*)> current) { sandbox_ = std::move(current); }
  /// Called by "Load best into sandbox".
  void set_load_into_sandbox(std::function<void(const TestSpec&)> load) { load_into_sandbox_ = std::move(load); }
  /// The `salsa` program a run starts (default: the one beside this program).
  void set_salsa_program(QString program);

  // ---- What the buttons do, callable without dialogs. "" or the one-line reason (also shown).
  /// Takes the sandbox's test: the table lists its tunable numbers, its behavior's parameters ticked.
  std::string from_sandbox();
  /// The tune file the page describes (checked by the core's tune reader, as `salsa tune` checks it),
  /// or "" with `why`; `canonical`: what OUT/tune.json records for it.
  std::string tune_json(std::string* why, std::string* canonical = nullptr) const;
  std::string save(const QString& file);
  /// Saves the tune file beside `out` as <out>.tune.json and starts `salsa tune` of it into `out`; a
  /// folder that holds this tune already is resumed.
  std::string run(const QString& out);
  void stop();
  bool running() const;
  bool wait(int ms);  ///< waits for a run to end, handling events (tests)
  /// Shows the tune in `out` (finished or not): its chart, and its winner for "Load best".
  std::string open_results(const QString& out);
  /// Loads OUT/best.json's test (the winner, on the first tuning world) into the sandbox.
  std::string load_best();

  // ---- For tests
  QTableWidget* parameters() const { return table_; }
  /// Ticks (or unticks) the row of `key` and sets its range (NaN: leave as is). False: no such row.
  bool set_parameter(const std::string& key, bool tuned, double min = std::nan(""), double max = std::nan(""));
  QComboBox* objective_box() const { return objective_; }
  QComboBox* goal_box() const { return goal_; }
  QComboBox* algorithm_box() const { return algorithm_; }
  NumberField* evaluations_box() const { return evaluations_; }
  NumberField* worlds_box() const { return worlds_; }
  NumberField* validation_box() const { return validation_; }
  QLineEdit* seed_box() const { return seed_; }
  NumberField* jobs_box() const { return jobs_; }
  QLineSeries* best_series() const { return best_; }
  QLineSeries* defaults_series() const { return defaults_; }
  QScatterSeries* candidates_series() const { return scores_; }
  QProgressBar* progress() const { return progress_; }
  QPushButton* load_best_button() const { return load_best_button_; }
  QString output_dir() const { return out_; }
  QString log_text() const;
  const QString& last_message() const { return last_message_; }

 private:
  void build();
  void fill_objectives();
  void update_chart();
  void show_message(const QString& text, bool error = true);
  /// The base test as a tune file's "test": resolved, without seed, repeat or the sandbox's live changes.
  std::string base_json() const;
  std::shared_ptr<const PluginHost> host_;
  std::vector<std::filesystem::path> plugin_dirs_;
  std::optional<TestSpec> base_;
  std::vector<TunableNumber> numbers_;  ///< the table's rows
  QLabel* base_label_ = nullptr;
  QTableWidget* table_ = nullptr;
  QComboBox* objective_ = nullptr;
  QComboBox* goal_ = nullptr;
  QComboBox* aggregate_ = nullptr;
  QComboBox* algorithm_ = nullptr;
  NumberField* evaluations_ = nullptr;
  NumberField* worlds_ = nullptr;
  NumberField* validation_ = nullptr;
  QCheckBox* racing_ = nullptr;
  QLineEdit* seed_ = nullptr;
  NumberField* jobs_ = nullptr;
  QPushButton* run_button_ = nullptr;
  QPushButton* stop_button_ = nullptr;
  QPushButton* load_best_button_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* state_ = nullptr;
  QPlainTextEdit* log_ = nullptr;
  QChartView* chart_view_ = nullptr;
  QLineSeries* best_ = nullptr;
  QLineSeries* defaults_ = nullptr;
  QScatterSeries* scores_ = nullptr;
  QValueAxis* x_ = nullptr;
  QValueAxis* y_ = nullptr;
  SalsaProcess* process_ = nullptr;
  QString out_;
  std::size_t budget_ = 0;  ///< evaluations of the tune shown (0: not known)
  std::function<std::optional<TestSpec>(std::string*)> sandbox_;
  std::function<void(const TestSpec&)> load_into_sandbox_;
  QString last_message_;
};

}  // namespace salsa::gui
