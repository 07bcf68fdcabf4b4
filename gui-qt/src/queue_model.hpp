#pragma once
// Queue mode's table: the tests of a queue, one row each, in the order they run. Rows are the
// experiments layer's tests (TestSpec), read and checked by the core exactly as `salsa run` reads
// them; the file saved is a queue `salsa run` accepts ({"tests": [...]}, every test resolved, with its
// seed), so reordering or editing one row never changes another row's world.
#include <QAbstractTableModel>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::gui {

class QueueModel : public QAbstractTableModel {
  Q_OBJECT
 public:
  enum Column { col_name, col_behavior, col_parameters, col_drones, col_map, col_targets, col_time, col_seed, col_status, col_result, column_count };
  enum class Status { pending, running, done, failed };

  explicit QueueModel(std::shared_ptr<const PluginHost> host, QObject* parent = nullptr);
  void set_host(std::shared_ptr<const PluginHost> host) { host_ = std::move(host); }
  /// salsa-gui --yes: queues over QueueOptions::max_tests tests are read and saved (as salsa run --yes).
  void set_allow_large(bool yes) { options_.yes = yes; }
  const QueueOptions& options() const { return options_; }

  int rowCount(const QModelIndex& parent = {}) const override;
  int columnCount(const QModelIndex& parent = {}) const override;
  QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;
  Qt::ItemFlags flags(const QModelIndex& index) const override;
  /// Name, drones, targets, time and seed are edited in place; the edited test is checked like a test
  /// file's, and a refused value changes nothing (last_error() says why).
  bool setData(const QModelIndex& index, const QVariant& value, int role = Qt::EditRole) override;
  bool removeRows(int row, int count, const QModelIndex& parent = {}) override;
  bool moveRows(const QModelIndex& source_parent, int source_row, int count, const QModelIndex& destination_parent,
                int destination_child) override;
  Qt::DropActions supportedDropActions() const override { return Qt::MoveAction; }

  // ---- Editing. Each returns "" or the one-line reason nothing changed.
  /// Appends tests (a name already in the queue gets "-2", "-3"...).
  std::string add(std::vector<TestSpec> tests);
  /// Replaces row `row` by `json` (a whole test object), checked like a test file's.
  std::string replace(int row, const std::string& json);
  /// Moves `row` up (-1) or down (+1).
  bool move(int row, int by);
  /// Replaces the queue by a file's tests (a test, a list, or a queue with sweeps and repeats, expanded).
  std::string load(const std::filesystem::path& file);
  /// Writes the queue file; then reads it back as `salsa run` would, which must give these tests.
  std::string save(const std::filesystem::path& file) const;
  /// The queue file's text: {"tests": [...]}, each test resolved (config.json's form).
  std::string queue_json() const;

  const TestSpec& test(int row) const { return rows_.at(static_cast<std::size_t>(row)).test; }
  std::string test_json(int row) const;  ///< pretty, as the row would be saved
  Status status(int row) const { return rows_.at(static_cast<std::size_t>(row)).status; }
  /// `result`: a finished test's outcome in words (the result column), e.g. "found 27 / 30 (90.0 %)".
  void set_status(int row, Status status, const std::string& message = {}, const std::string& result = {});
  void clear_statuses();
  const std::string& last_error() const { return last_error_; }

 Q_SIGNALS:
  /// A cell edit was refused: why (the page shows it; the row keeps its value).
  void edit_refused(const QString& why);

 private:
  struct Row {
    TestSpec test;
    Status status = Status::pending;
    std::string message;  ///< why it failed
    std::string result;   ///< a finished test's outcome
  };
  std::string unique_name(const std::string& name, int except_row = -1) const;
  std::shared_ptr<const PluginHost> host_;
  QueueOptions options_;
  std::vector<Row> rows_;
  mutable std::string last_error_;
};

}  // namespace salsa::gui
