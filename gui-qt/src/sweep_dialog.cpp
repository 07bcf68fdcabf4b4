// "Add sweep": the dialog that makes a queue's sweep over the sandbox's test, counting its tests as you type.
#include "sweep_dialog.hpp"

#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include "number_field.hpp"
#include <QTemporaryDir>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace salsa::gui {

using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

QString q(const std::string& s) { return QString::fromStdString(s); }

/// "1, 2, 3" → [1, 2, 3]; "0.5:2:0.5" → {"from": 0.5, "to": 2, "step": 0.5}.
std::optional<json> values_of(const QString& text, std::string* why) {
  const QString t = text.trimmed();
  if (t.contains(':')) {
    const QStringList parts = t.split(':');
    bool ok[3] = {false, false, false};
    if (parts.size() == 3) {
      json range{{"from", parts[0].trimmed().toDouble(&ok[0])}, {"to", parts[1].trimmed().toDouble(&ok[1])},
                 {"step", parts[2].trimmed().toDouble(&ok[2])}};
      if (ok[0] && ok[1] && ok[2]) return range;
    }
    *why = "'" + t.toStdString() + "': a range is from:to:step, e.g. 0.5:2:0.5";
    return std::nullopt;
  }
  json list = json::array();
  for (const QString& part : t.split(',', Qt::SkipEmptyParts)) {
    bool ok = false;
    const double v = part.trimmed().toDouble(&ok);
    if (!ok) {
      *why = "'" + part.trimmed().toStdString() + "' is not a number (values: 1, 2, 3 or from:to:step)";
      return std::nullopt;
    }
    list.push_back(v);
  }
  if (list.empty()) {
    *why = "no values given (values: 1, 2, 3 or from:to:step)";
    return std::nullopt;
  }
  return list;
}

}  // namespace

SweepDialog::SweepDialog(std::shared_ptr<const PluginHost> host, const TestSpec& base, QWidget* parent, QueueOptions options)
    : QWidget(parent), host_(std::move(host)), base_(base), options_(options) {
  auto* form = new QFormLayout(this);
  form->addRow(new QLabel("Everything else (map, targets, drone, time) is the sandbox's test. Every behavior meets the "
                          "same worlds: seeds are paired by repeat and world."));
  behaviors_ = new QListWidget;
  for (const auto& e : host_->behaviors()) {
    auto* item = new QListWidgetItem(q(e.factory.name), behaviors_);
    item->setCheckState(e.factory.name == base_.groups[0].behavior.name ? Qt::Checked : Qt::Unchecked);
  }
  behaviors_->setMaximumHeight(110);
  form->addRow("behaviors", behaviors_);
  for (int i = 0; i < 3; ++i) {
    auto* which = new QComboBox;
    which->addItem("(no parameter)");
    for (const auto& e : host_->behaviors())
      for (const auto& p : e.factory.parameters)
        which->addItem(q(e.factory.name + "." + p.name), q(p.range() + (p.description.empty() ? "" : ": " + p.description)));
    auto* values = new QLineEdit;
    values->setPlaceholderText("1, 2, 3  or  from:to:step");
    auto* row = new QHBoxLayout;
    row->addWidget(which, 1);
    row->addWidget(values, 1);
    form->addRow(QString("parameter %1").arg(i + 1), row);
    connect(which, &QComboBox::currentIndexChanged, this, [which, values] { values->setToolTip(which->currentData().toString()); });
    connect(which, &QComboBox::currentIndexChanged, this, &SweepDialog::update_count);
    connect(values, &QLineEdit::textChanged, this, &SweepDialog::update_count);
    axes_.emplace_back(which, values);
  }
  drones_ = new QLineEdit(QString::number(base_.groups[0].drones));
  drones_->setPlaceholderText("10, 20, 30  or  10:50:10");
  form->addRow("swarm sizes", drones_);
  repeats_ = new NumberField({"repeats", 1, 1, static_cast<double>(max_queue_tests), "", "", 1});
  repeats_->setToolTip(QString::fromStdString("each test run this many times on other worlds (allowed: " + repeats_->spec().range() + ")"));
  form->addRow("repeats", repeats_);
  seed_ = new QLineEdit("1");  // a line: seeds go to 2^53, past a spin box's int
  seed_->setObjectName("queue_seed");
  seed_->setToolTip(QString("the queue seed, a whole number in [0, %1]: each repeat's worlds come from it").arg(max_seed));
  form->addRow("queue seed", seed_);
  count_ = new QLabel;
  count_->setWordWrap(true);
  form->addRow(count_);
  connect(behaviors_, &QListWidget::itemChanged, this, &SweepDialog::update_count);
  connect(drones_, &QLineEdit::textChanged, this, &SweepDialog::update_count);
  connect(repeats_, &NumberField::valueChanged, this, &SweepDialog::update_count);
  connect(seed_, &QLineEdit::textChanged, this, &SweepDialog::update_count);
  update_count();
}

void SweepDialog::set_axis(int row, const QString& behavior_param, const QString& values) {
  auto [which, text] = axes_.at(static_cast<std::size_t>(row));
  which->setCurrentIndex(std::max(0, which->findText(behavior_param)));
  text->setText(values);
}

std::string SweepDialog::queue_json(std::string* why) const {
  json behaviors = json::array();
  for (int i = 0; i < behaviors_->count(); ++i) {
    const auto* item = behaviors_->item(i);
    if (item->checkState() != Qt::Checked) continue;
    const std::string name = item->text().toStdString();
    json params = json::object();
    for (const auto& [which, text] : axes_) {
      const std::string key = which->currentText().toStdString();
      if (which->currentIndex() == 0 || !key.starts_with(name + ".")) continue;
      auto values = values_of(text->text(), why);
      if (!values) {
        *why = key + ": " + *why;
        return {};
      }
      params[key.substr(name.size() + 1)] = *values;
    }
    behaviors.push_back(params.empty() ? json(name) : json{{"name", name}, {"params", params}});
  }
  if (behaviors.empty()) {
    *why = "choose at least one behavior";
    return {};
  }
  for (const auto& [which, text] : axes_)
    if (which->currentIndex() != 0) {
      const std::string key = which->currentText().toStdString();
      bool used = false;
      for (const auto& b : behaviors) used |= b.is_object() && key.starts_with(b["name"].get<std::string>() + ".");
      if (!used) {
        *why = key + ": its behavior is not chosen";
        return {};
      }
    }
  auto drones = values_of(drones_->text(), why);
  if (!drones) {
    *why = "swarm sizes: " + *why;
    return {};
  }
  // The sandbox's test, less what the axes and the queue decide.
  json test = json::parse(resolved_json(base_, *host_));
  for (const char* key : {"name", "behavior", "drones", "seed", "repeat", "versions", "changes"}) test.erase(key);
  // Read as JSON, so a whole number is kept exactly; the queue reader checks its range and says so.
  json seed;
  try {
    seed = json::parse(seed_->text().trimmed().toStdString());
  } catch (const std::exception&) {
  }
  // Checked here too: the reader takes numbers as doubles, and 2^53 + 1 would round into range.
  if (!seed.is_number_unsigned() || seed.get<std::uint64_t>() > max_seed) {
    *why = "queue seed: \"" + seed_->text().trimmed().toStdString() + "\" is not a seed (allowed: whole number in [0, " + std::to_string(max_seed) + "])";
    return {};
  }
  const json queue{{"seed", seed}, {"repeats", repeats_->whole()},
                   {"sweep", {{"test", test}, {"behaviors", behaviors}, {"drones", *drones}}}};
  return queue.dump(2);
}

std::optional<std::vector<TestSpec>> SweepDialog::expand(std::string* why) const {
  const std::string text = queue_json(why);
  if (text.empty()) return std::nullopt;
  // Expanded by the core from a file, exactly as `salsa run` would expand it.
  QTemporaryDir dir;
  const fs::path file = fs::path(dir.path().toStdString()) / "sweep.json";
  std::ofstream(file) << text;
  try {
    return load_queue(file, *host_, options_).tests;
  } catch (const std::exception& e) {
    *why = e.what();
    if (auto at = why->find(file.string()); at != std::string::npos) why->replace(at, file.string().size(), "sweep");
    return std::nullopt;
  }
}

void SweepDialog::update_count() {
  std::string why;
  const auto tests = expand(&why);
  count_->setStyleSheet(tests ? "" : "color: #b00020");
  count_->setText(tests ? QString("makes <b>%1</b> tests").arg(tests->size()) : q(why));
  Q_EMIT changed();
}

}  // namespace salsa::gui
