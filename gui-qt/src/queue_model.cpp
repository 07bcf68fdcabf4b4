#include "queue_model.hpp"

#include <QColor>

#include <nlohmann/json.hpp>

#include <set>

#include "salsa/core/experiments/queue.hpp"
#include "format.hpp"
#include "save_checked.hpp"

namespace salsa::gui {

using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

QString q(const std::string& s) { return QString::fromStdString(s); }

/// "a=1 b=2": the parameters that differ from the declared defaults ("" when none do).
std::string non_default(const PluginChoice& choice, const Parameters& schema) {
  std::string text = describe_choice(choice, schema);
  const auto open = text.find('(');
  return open == std::string::npos ? std::string() : text.substr(open + 1, text.size() - open - 2);
}

}  // namespace

QueueModel::QueueModel(std::shared_ptr<const PluginHost> host, QObject* parent) : QAbstractTableModel(parent), host_(std::move(host)) {}

int QueueModel::rowCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : static_cast<int>(rows_.size()); }
int QueueModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : column_count; }

QVariant QueueModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (role != Qt::DisplayRole) return {};
  if (orientation == Qt::Vertical) return section + 1;
  static const char* const names[] = {"name", "behavior", "parameters", "drones", "map", "targets", "time (s)", "seed", "status", "result"};
  return section >= 0 && section < column_count ? QVariant(names[section]) : QVariant();
}

Qt::ItemFlags QueueModel::flags(const QModelIndex& index) const {
  if (!index.isValid()) return Qt::ItemIsDropEnabled;
  Qt::ItemFlags f = Qt::ItemIsEnabled | Qt::ItemIsSelectable | Qt::ItemIsDragEnabled;
  switch (index.column()) {
    case col_name: case col_drones: case col_targets: case col_time: case col_seed: f |= Qt::ItemIsEditable; break;
    default: break;
  }
  return f;
}

QVariant QueueModel::data(const QModelIndex& index, int role) const {
  if (!index.isValid() || index.row() >= rowCount() || index.column() >= column_count) return {};
  const Row& r = rows_[static_cast<std::size_t>(index.row())];
  const TestSpec& t = r.test;
  if (role == Qt::ToolTipRole) {
    if (index.column() == col_status && !r.message.empty()) return q(r.message);
    if (index.column() == col_map && !t.map_file.empty()) return q(t.map_file);
    return {};
  }
  if (role == Qt::BackgroundRole && index.column() == col_status) {
    switch (r.status) {
      case Status::done: return QColor(214, 240, 214);
      case Status::failed: return QColor(250, 210, 210);
      case Status::running: return QColor(210, 226, 250);
      default: return {};
    }
  }
  if (role == Qt::TextAlignmentRole) {
    switch (index.column()) {
      case col_drones: case col_targets: case col_time: case col_seed: return int(Qt::AlignRight | Qt::AlignVCenter);
      default: return {};
    }
  }
  if (role != Qt::DisplayRole && role != Qt::EditRole) return {};
  // A number is edited as text (a line, not a spin box that would clamp or drop keys): setData reads it
  // as a test file's number and the core's checks accept or refuse it in one line.
  if (role == Qt::EditRole) switch (index.column()) {
      case col_drones: return q(format::number(static_cast<double>(t.drone_total())));
      case col_targets: return q(format::number(static_cast<double>(t.targets)));
      case col_time: return q(format::number(t.time));
      case col_seed: return QString::number(static_cast<qulonglong>(t.seed));
      default: break;
    }
  switch (index.column()) {
    case col_name: return q(t.name);
    case col_behavior: return q(t.groups[0].behavior.name);
    case col_parameters: {
      try {
        const std::string changed = non_default(t.groups[0].behavior, host_->behavior(t.groups[0].behavior.name).factory.parameters);
        return changed.empty() ? QString("defaults") : q(changed);
      } catch (const std::exception&) {
        return {};  // the plugin is gone since (a rescan): the row still runs where it is installed
      }
    }
    case col_drones: return static_cast<qulonglong>(t.drone_total());
    case col_map: {
      if (!t.map_file.empty()) return q(fs::path(t.map_file).filename().string());
      try {
        return q(describe_choice(t.map, host_->map(t.map.name).factory.parameters));
      } catch (const std::exception&) {
        return q(t.map.name);
      }
    }
    case col_targets:
      return t.targets ? q(std::to_string(t.targets) + " " + t.target.name) : QString("0");
    case col_time: return t.time;
    case col_seed: return static_cast<qulonglong>(t.seed);
    case col_status:
      switch (r.status) {
        case Status::pending: return "pending";
        case Status::running: return "running";
        case Status::done: return "done";
        case Status::failed: return q("failed: " + r.message);
      }
      break;
    case col_result: return q(r.result);
  }
  return {};
}

bool QueueModel::setData(const QModelIndex& index, const QVariant& value, int role) {
  if (!index.isValid() || role != Qt::EditRole || !(flags(index) & Qt::ItemIsEditable)) return false;
  json j = json::parse(test_json(index.row()));
  const std::string where = "queue row " + std::to_string(index.row() + 1) + ": ";
  // A typed cell is text: read as a JSON number (whole numbers exactly, so seeds up to 2^53 stay
  // themselves), and text that is no number is refused, not read as 0.
  auto number = [&](const char* field) -> std::optional<json> {
    if (value.typeId() != QMetaType::QString) {
      if (value.typeId() == QMetaType::ULongLong) return json(value.toULongLong());
      return json(value.toDouble());
    }
    const std::string text = value.toString().trimmed().toStdString();
    try {
      if (json n = json::parse(text); n.is_number()) return n;
    } catch (const std::exception&) {
    }
    last_error_ = where + field + ": \"" + text + "\" is not a number";
    return std::nullopt;
  };
  std::optional<json> n;
  switch (index.column()) {
    case col_name: j["name"] = value.toString().toStdString(); break;
    case col_drones: if ((n = number("drones"))) j["drones"] = *n; break;
    case col_targets: if ((n = number("targets.count"))) j["targets"]["count"] = *n; break;
    case col_time: if ((n = number("time"))) j["time"] = *n; break;
    case col_seed: if ((n = number("seed"))) j["seed"] = *n; break;
    default: return false;
  }
  const std::string why = index.column() != col_name && !n ? last_error_ : replace(index.row(), j.dump());
  if (!why.empty()) Q_EMIT edit_refused(QString::fromStdString(why));
  return why.empty();
}

std::string QueueModel::replace(int row, const std::string& text) {
  last_error_.clear();
  if (row < 0 || row >= rowCount()) return last_error_ = "no row " + std::to_string(row + 1);
  try {
    TestSpec t = parse_test(text, "queue row " + std::to_string(row + 1), *host_);
    if (unique_name(t.name, row) != t.name) return last_error_ = "queue row " + std::to_string(row + 1) + ": name: '" + t.name + "' is taken (names are output folders: each test needs its own)";
    rows_[static_cast<std::size_t>(row)] = {std::move(t), Status::pending, {}, {}};
  } catch (const std::exception& e) {
    return last_error_ = e.what();
  }
  Q_EMIT dataChanged(index(row, 0), index(row, column_count - 1));
  return {};
}

std::string QueueModel::unique_name(const std::string& wanted, int except_row) const {
  std::set<std::string> taken;
  for (std::size_t i = 0; i < rows_.size(); ++i)
    if (static_cast<int>(i) != except_row) taken.insert(rows_[i].test.name);
  std::string candidate = wanted;
  for (int k = 2; taken.count(candidate); ++k) candidate = wanted + "-" + std::to_string(k);
  return candidate;
}

std::string QueueModel::add(std::vector<TestSpec> tests) {
  last_error_.clear();
  if (tests.empty()) return {};
  beginInsertRows({}, rowCount(), rowCount() + static_cast<int>(tests.size()) - 1);
  for (auto& t : tests) {
    t.name = unique_name(t.name);
    t.seed_given = true;  // the row keeps its world wherever it moves
    rows_.push_back({std::move(t), Status::pending, {}, {}});
  }
  endInsertRows();
  return {};
}

bool QueueModel::removeRows(int row, int count, const QModelIndex& parent) {
  if (parent.isValid() || row < 0 || count <= 0 || row + count > rowCount()) return false;
  beginRemoveRows({}, row, row + count - 1);
  rows_.erase(rows_.begin() + row, rows_.begin() + row + count);
  endRemoveRows();
  return true;
}

bool QueueModel::moveRows(const QModelIndex& source_parent, int source_row, int count, const QModelIndex& destination_parent,
                          int destination) {
  if (source_parent.isValid() || destination_parent.isValid() || count <= 0 || source_row < 0 ||
      source_row + count > rowCount() || destination < 0 || destination > rowCount() ||
      (destination >= source_row && destination <= source_row + count))
    return false;
  if (!beginMoveRows({}, source_row, source_row + count - 1, {}, destination)) return false;
  std::vector<Row> moved(std::make_move_iterator(rows_.begin() + source_row), std::make_move_iterator(rows_.begin() + source_row + count));
  rows_.erase(rows_.begin() + source_row, rows_.begin() + source_row + count);
  const int at = destination > source_row ? destination - count : destination;
  rows_.insert(rows_.begin() + at, std::make_move_iterator(moved.begin()), std::make_move_iterator(moved.end()));
  endMoveRows();
  return true;
}

bool QueueModel::move(int row, int by) {
  const int to = row + by;
  if (row < 0 || row >= rowCount() || to < 0 || to >= rowCount() || by == 0) return false;
  return moveRows({}, row, 1, {}, by > 0 ? to + 1 : to);
}

std::string QueueModel::test_json(int row) const { return json::parse(resolved_json(test(row), *host_)).dump(2); }

std::string QueueModel::queue_json() const {
  json tests = json::array();
  for (int i = 0; i < rowCount(); ++i) tests.push_back(json::parse(resolved_json(test(i), *host_)));
  return json{{"tests", std::move(tests)}}.dump(2) + "\n";
}

std::string QueueModel::load(const fs::path& file) {
  last_error_.clear();
  std::vector<TestSpec> tests;
  try {
    tests = load_queue(file, *host_, options_).tests;
  } catch (const std::exception& e) {
    return last_error_ = e.what();
  }
  beginResetModel();
  rows_.clear();
  for (auto& t : tests) {
    t.seed_given = true;
    rows_.push_back({std::move(t), Status::pending, {}, {}});
  }
  endResetModel();
  return {};
}

std::string QueueModel::save(const fs::path& file) const {
  last_error_.clear();
  if (rows_.empty()) return last_error_ = file.string() + ": the queue holds no tests (add one first)";
  // Read back as `salsa run` reads it, and compared row by row.
  return last_error_ = save_checked(file, queue_json(), [this](const fs::path& aside) -> std::string {
    const auto back = load_queue(aside, *host_, options_).tests;
    if (back.size() != rows_.size()) return "the file reads back as " + std::to_string(back.size()) + " tests";
    for (std::size_t i = 0; i < back.size(); ++i)
      if (resolved_json(back[i], *host_) != resolved_json(rows_[i].test, *host_)) return "row " + std::to_string(i + 1) + " reads back differently";
    return {};
  });
}

void QueueModel::set_status(int row, Status s, const std::string& message, const std::string& result) {
  if (row < 0 || row >= rowCount()) return;
  auto& r = rows_[static_cast<std::size_t>(row)];
  if (r.status == s && r.message == message && r.result == result) return;
  r.status = s;
  r.message = message;
  r.result = result;
  Q_EMIT dataChanged(index(row, col_status), index(row, col_result));
}

void QueueModel::clear_statuses() {
  for (int i = 0; i < rowCount(); ++i) set_status(i, Status::pending);
}

}  // namespace salsa::gui
