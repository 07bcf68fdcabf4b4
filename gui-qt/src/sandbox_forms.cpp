// The sandbox's forms: the controls that show, build and read a test's settings (set-up, groups, drones;
// the models' boxes: sandbox_models.cpp).
#include <QComboBox>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSettings>
#include <QTimer>
#include <QToolButton>
#include <QVBoxLayout>
#include <algorithm>
#include <charconv>
#include <nlohmann/json.hpp>

#include "number_field.hpp"
#include "param_panel.hpp"
#include "salsa/core/files/names.hpp"
#include "sandbox_page.hpp"

namespace salsa::gui {
namespace {

using json = nlohmann::ordered_json;

QString q(const std::string& s) { return QString::fromStdString(s); }

json params_json(const ParamPanel* panel) {
  json out = json::object();
  for (const Parameter& p : panel->schema()) out[p.name] = panel->value(p.name);
  return out;
}

json drone_json(const DroneConfig& d) {
  json out = {{"name", d.name}};
  for (const DroneProperty& p : salsa::drone_schema()) out[p.spec.name] = p.get(d);
  return out;
}

double drone_value(const DroneConfig& d, const std::string& name) { return salsa::drone_schema().find(name)->get(d); }

/// The map box's entry while a map file is in use (not a map plugin's name: names have no spaces).
const QString map_file_prefix = "map file: ";

/// A button that folds `panel` away (hidden until it is checked): for a long section seldom wanted.
QToolButton* fold_button(const char* name, const QString& text, const QString& tip, QWidget* panel) {
  auto* button = new QToolButton;
  button->setObjectName(name);
  button->setText(text);
  button->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
  button->setArrowType(Qt::RightArrow);
  button->setCheckable(true);
  button->setAutoRaise(true);
  button->setToolTip(tip);
  panel->hide();
  QObject::connect(button, &QToolButton::toggled, panel, [button, panel](bool open) {
    panel->setVisible(open);
    button->setArrowType(open ? Qt::DownArrow : Qt::RightArrow);
  });
  return button;
}

}  // namespace

void SandboxPage::build_forms(QVBoxLayout* column) {
  // With two or more groups: whose behavior, drone count and drone the controls below show and change.
  group_row_ = new QWidget;
  auto* group_line = new QHBoxLayout(group_row_);
  group_line->setContentsMargins(0, 0, 0, 0);
  group_ = new QComboBox;
  group_->setObjectName("group");
  group_->setToolTip("the group of drones whose behavior, drone count and drone properties the controls below edit");
  group_line->addWidget(new QLabel("<b>Group</b>"));
  group_line->addWidget(group_, 1);
  group_row_->hide();
  column->addWidget(group_row_);

  auto* setup = new QGroupBox("Test (changing these starts over)");
  auto* form = new QFormLayout(setup);
  behavior_ = new QComboBox;
  behavior_->setObjectName("behavior");
  for (const auto& e : host_->behaviors()) behavior_->addItem(q(e.factory.name));
  behavior_->setToolTip("the behavior the drones (of the chosen group) run");
  form->addRow("behavior", behavior_);
  map_ = new QComboBox;
  map_->setObjectName("map");
  for (const auto& e : host_->maps())
    if (e.factory.name != "json") map_->addItem(q(e.factory.name));
  map_->setToolTip("a generated map (a map plugin), or the map file in use");
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
  target_kind_->setObjectName("target_kind");
  for (const auto& e : host_->target_kinds()) target_kind_->addItem(q(e.factory.name));
  form->addRow("target kind", target_kind_);
  // The ranges a test file allows (test_reader.cpp); one new world per edit, not one per keystroke.
  targets_ = new NumberField({"targets", 0, 0, 10'000'000, "", "", 1});
  targets_->setToolTip("targets placed on the map (allowed: whole number in [0, 10000000])");
  form->addRow("targets", targets_);
  // A line, not a spin box: a QSpinBox holds an int, and seeds go to 2^53.
  seed_ = new QLineEdit;
  seed_->setObjectName("seed");
  seed_->setToolTip(QString("the test's seed: a whole number in [0, %1] (Enter applies it)").arg(max_seed));
  form->addRow("seed", seed_);
  physics_ = new QComboBox;
  physics_->setObjectName("physics");
  physics_->addItems({"box2d", "light"});
  physics_->setToolTip("box2d: Box2D's rigid bodies (the default); light: salsa moves the drones itself, in parallel, "
                       "for swarms of 10,000 and more (docs/test-format.md#physics)");
  form->addRow("physics", physics_);
  column->addWidget(setup);

  auto* live = new QGroupBox("Live (recorded; kept by Save as test)");
  auto* live_form = new QVBoxLayout(live);
  auto* drones_row = new QFormLayout;
  drones_ = new NumberField({"drones", 1, 1, 1'000'000, "", "", 1});
  drones_->setToolTip("drones added at the (chosen group's) base, or its highest ids removed (allowed: whole number in [1, 1000000])");
  drones_row->addRow("drones", drones_);
  live_form->addLayout(drones_row);
  live_form->addWidget(new QLabel("<b>Behavior parameters</b>"));
  behavior_panel_ = new ParamPanel;
  live_form->addWidget(behavior_panel_);
  auto* drone_row = new QHBoxLayout;
  drone_row->addWidget(new QLabel("<b>Drone</b>"));
  drone_config_ = new QComboBox;
  drone_config_->setObjectName("drone_config");
  drone_config_->setToolTip("a named drone configuration: choosing one applies its values");
  drone_row->addWidget(drone_config_, 1);
  auto* save_config = new QPushButton("Save as…");
  save_config->setToolTip("save the values below as a named configuration");
  drone_row->addWidget(save_config);
  live_form->addLayout(drone_row);
  drone_panel_ = new ParamPanel;
  drone_panel_->set_schema(drone_schema(DroneSection::body));
  live_form->addWidget(drone_panel_);
  // The energy model's nine properties make a long panel: folded away until a battery is wanted.
  battery_panel_ = new ParamPanel;
  battery_panel_->setObjectName("battery_panel");
  battery_panel_->set_schema(drone_schema(DroneSection::energy));
  // 0 means "off" for these two: say so rather than show "0.0 Wh".
  battery_panel_->spin_box("battery_capacity")->set_special_text("none");
  battery_panel_->spin_box("charge_power")->set_special_text("no charging");
  battery_toggle_ = fold_button("battery_toggle", "Battery and power model",
                                "battery capacity (0 Wh: no battery model), the rotary-wing power model of Zeng, Xu & Zhang (2019) "
                                "and charging at the base",
                                battery_panel_);
  live_form->addWidget(battery_toggle_);
  live_form->addWidget(battery_panel_);
  // Sensor noise, off (all 0) by default: folded away likewise.
  noise_panel_ = new ParamPanel;
  noise_panel_->setObjectName("noise_panel");
  noise_panel_->set_schema(drone_schema(DroneSection::noise));
  noise_toggle_ = fold_button("noise_toggle", "Sensor noise",
                              "noise on the drone's own position, its neighbours and obstacle rays; missed targets and false "
                              "detections (all 0: perfect sensors)",
                              noise_panel_);
  live_form->addWidget(noise_toggle_);
  live_form->addWidget(noise_panel_);
  auto* fine = new QLabel("Sliders: click one, then the arrow keys move it one fine step; ranges over decades are logarithmic.");
  fine->setWordWrap(true);
  fine->setStyleSheet("color: palette(mid)");
  live_form->addWidget(fine);
  column->addWidget(live);

  // A box per model of the test's sections (failures, comm, wind, any added), from its declaration.
  build_model_boxes(column);

  // Start state: a new load, once the event loop is back. Live values: a recorded change.
  auto reload = [this] {
    if (!updating_) schedule_reload();
  };
  // Another behavior or map starts from its own declared defaults.
  connect(behavior_, &QComboBox::currentTextChanged, this, [this](const QString& name) {
    if (updating_) return;
    const auto& e = host_->behavior(name.toStdString());
    behavior_panel_->set_schema(e.factory.parameters, ParameterValues(e.factory.parameters));
    schedule_reload();
  });
  connect(map_, &QComboBox::currentTextChanged, this, [this](const QString& name) {
    if (updating_ || name.startsWith(map_file_prefix)) return;
    map_file_.clear();
    for (int i = map_->count() - 1; i >= 0; --i)
      if (map_->itemText(i).startsWith(map_file_prefix)) map_->removeItem(i);
    const auto& e = host_->map(name.toStdString());
    map_panel_->set_schema(e.factory.parameters, ParameterValues(e.factory.parameters));
    schedule_reload();
  });
  connect(map_panel_, &ParamPanel::changed, this, reload);
  connect(target_kind_, &QComboBox::currentTextChanged, this, reload);
  connect(targets_, &NumberField::valueChanged, this, reload);
  connect(physics_, &QComboBox::currentTextChanged, this, reload);
  connect(seed_, &QLineEdit::editingFinished, this, &SandboxPage::seed_edited);
  connect(open_map_button, &QPushButton::clicked, this, &SandboxPage::ask_open_map);
  connect(group_, &QComboBox::currentTextChanged, this, [this](const QString& name) {
    if (updating_ || name.isEmpty()) return;
    group_name_ = name.toStdString();
    if (auto t = engine_.current_test()) show_test(*t);
  });
  connect(drones_, &NumberField::valueChanged, this, [this](double n) {
    if (!updating_) live_change(group_key("drones"), n);
  });
  connect(behavior_panel_, &ParamPanel::changed, this, [this](const std::string& name, double v) {
    if (!updating_) live_change(group_key("behavior.params." + name), v);
  });
  for (ParamPanel* drone : drone_panels())
    connect(drone, &ParamPanel::changed, this, [this](const std::string& name, double v) {
      if (!updating_) live_change(group_key("drone." + name), v);
    });
  connect(drone_config_, &QComboBox::activated, this, [this](int) { apply_drone_config(drone_config_->currentText()); });
  connect(save_config, &QPushButton::clicked, this, &SandboxPage::save_drone_config);
}

// ---------------------------------------------------------------- start states

std::optional<TestSpec> SandboxPage::spec_from_controls(std::string* why) {
  // What the controls do not show (dt, log interval, spawn, metrics, ...) comes from the test opened
  // last; the rest from the controls. Parsed like a test file, so the CLI's checks and messages apply.
  json j = json::parse(resolved_json(file_base_, *host_));
  j.erase("versions");
  j.erase("changes");
  // The groups as they run now (live changes kept), the chosen one as the controls say.
  const std::optional<TestSpec> now = loaded_ ? engine_.current_test() : std::nullopt;
  const TestSpec& groups_from = now && now->groups.size() == file_base_.groups.size() ? *now : file_base_;
  if (file_base_.named_groups) j["groups"] = json::parse(resolved_json(groups_from, *host_))["groups"];
  const std::size_t gi = chosen_group(groups_from);
  json& group = file_base_.named_groups ? j["groups"][gi] : j;
  group["behavior"] = {{"name", behavior_->currentText().toStdString()}, {"params", params_json(behavior_panel_)}};
  DroneConfig d = groups_from.groups[gi].drone;
  d.name = drone_config_->currentText().toStdString();
  for (ParamPanel* panel : drone_panels())
    for (const Parameter& p : panel->schema()) salsa::drone_schema().find(p.name)->set(d, panel->value(p.name));
  group["drone"] = drone_json(d);
  group["drones"] = drones_->whole();
  models_json(j);
  if (!map_file_.isEmpty()) j["map"] = {{"file", map_file_.toStdString()}};
  else j["map"] = {{"name", map_->currentText().toStdString()}, {"params", params_json(map_panel_)}};
  const bool same_kind = target_kind_->currentText().toStdString() == file_base_.target.name;
  j["targets"] = {{"kind", target_kind_->currentText().toStdString()}, {"count", targets_->whole()}};
  if (same_kind) j["targets"]["params"] = json::parse(resolved_json(file_base_, *host_))["targets"]["params"];
  j["seed"] = seed_value_;
  j.erase("physics");
  if (physics_->currentText() == "light") j["physics"] = "light";  // box2d, the default, is written as none
  try {
    return parse_test(j.dump(), "sandbox", *host_);
  } catch (const std::exception& e) {
    if (why) *why = e.what();
    return std::nullopt;
  }
}

void SandboxPage::schedule_reload() {
  if (reload_due_) return;
  reload_due_ = true;
  QTimer::singleShot(0, this, [this] {
    if (reload_due_) reload_from_controls();
  });
}

void SandboxPage::reload_from_controls() {
  reload_due_ = false;
  std::string why;
  const auto spec = spec_from_controls(&why);
  if (!spec) {
    show_message(q(why));
    if (loaded_) show_test(*engine_.current_test());
    return;
  }
  load(*spec);
}

void SandboxPage::seed_edited() {
  const std::string text = seed_->text().trimmed().toStdString();
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || v > max_seed) {
    const bool was = updating_;
    updating_ = true;
    seed_->setText(QString::number(seed_value_));
    updating_ = was;
    show_message(QString("seed: \"%1\" is not a seed (allowed: whole number in [0, %2])").arg(q(text)).arg(max_seed));
    return;
  }
  seed_->setText(QString::number(v));  // "007" shows as 7
  if (v == seed_value_ || updating_) return;
  seed_value_ = v;
  schedule_reload();
}

std::size_t SandboxPage::chosen_group(const TestSpec& t) const {
  return static_cast<std::size_t>(std::max(0, t.group_index(group_name_)));
}

std::string SandboxPage::group_key(const std::string& rest) const {
  if (!loaded_ || loaded_->groups.size() < 2) return rest;
  return "groups." + loaded_->groups[chosen_group(*loaded_)].name + "." + rest;
}

void SandboxPage::show_test(const TestSpec& t) {
  const bool was = updating_;
  updating_ = true;
  // The group box: the test's groups, the chosen one kept by name (the first when it is gone).
  group_->clear();
  for (const GroupSpec& g : t.groups) group_->addItem(q(g.name));
  const std::size_t gi = chosen_group(t);
  group_name_ = t.groups[gi].name;
  group_->setCurrentIndex(static_cast<int>(gi));
  group_row_->setVisible(t.groups.size() > 1);
  const GroupSpec& group = t.groups[gi];
  behavior_->setCurrentText(q(group.behavior.name));
  behavior_panel_->set_schema(host_->behavior(group.behavior.name).factory.parameters, group.behavior.params);
  for (int i = map_->count() - 1; i >= 0; --i)
    if (map_->itemText(i).startsWith(map_file_prefix)) map_->removeItem(i);
  if (t.map.name == "json") {
    // The map box names the file in use: "forest" there would say a generated map runs.
    map_file_ = q(t.map_file);
    const QString item = map_file_prefix + QFileInfo(map_file_).fileName();
    map_->insertItem(0, item);
    map_->setItemData(0, map_file_, Qt::ToolTipRole);
    map_->setCurrentIndex(0);
    map_file_label_->setText(map_file_);
    map_file_label_->setToolTip(map_file_);
    map_panel_->set_schema({});
  } else {
    map_file_.clear();
    map_file_label_->setText("(generated)");
    map_file_label_->setToolTip({});
    map_->setCurrentText(q(t.map.name));
    map_panel_->set_schema(host_->map(t.map.name).factory.parameters, t.map.params);
  }
  target_kind_->setCurrentText(q(t.target.name));
  targets_->setValue(static_cast<double>(t.targets));
  seed_value_ = t.seed;
  seed_->setText(QString::number(t.seed));
  physics_->setCurrentText(t.physics == PhysicsMode::light ? "light" : "box2d");
  drones_->setValue(static_cast<double>(group.drones));
  // The box names the configuration the values are (live changes may have made them another's).
  const std::vector<DroneConfig> configs = drone_configs();
  const auto same = std::find_if(configs.begin(), configs.end(), [&](const DroneConfig& c) {
    return std::all_of(salsa::drone_schema().begin(), salsa::drone_schema().end(),
                       [&](const DroneProperty& p) { return p.get(c) == p.get(group.drone); });
  });
  const QString shown = q(same != configs.end() ? same->name : group.drone.name);
  drone_config_->clear();
  for (const DroneConfig& c : configs) drone_config_->addItem(q(c.name));
  if (drone_config_->findText(shown) < 0) drone_config_->addItem(shown);
  drone_config_->setCurrentText(shown);
  show_drone(group.drone);
  if (group.drone.battery_capacity > 0) battery_toggle_->setChecked(true);  // a battery in use is shown
  if (section_in_use(group.drone, DroneSection::noise)) noise_toggle_->setChecked(true);  // so is noise
  show_models(t);
  updating_ = was;
}

void SandboxPage::show_drone(const DroneConfig& d) {
  for (ParamPanel* panel : drone_panels())
    for (const Parameter& p : panel->schema()) panel->set_value(p.name, drone_value(d, p.name));
}

// ---------------------------------------------------------------- drone configurations

std::vector<DroneConfig> SandboxPage::drone_configs() const {
  std::vector<DroneConfig> all = builtin_drone_configs();
  QSettings settings;
  const auto saved = settings.value("drone_configs").toString().toStdString();
  if (saved.empty()) return all;
  try {
    const json configs = json::parse(saved);  // named: items() of a temporary would dangle
    for (const auto& [name, v] : configs.items()) {
      DroneConfig d;
      d.name = name;
      for (const DroneProperty& p : salsa::drone_schema()) p.set(d, v.value(p.spec.name, p.get(d)));
      all.push_back(d);
    }
  } catch (const std::exception&) {
    // A damaged settings entry: the built-in configurations still work.
  }
  return all;
}

void SandboxPage::apply_drone_config(const QString& name) {
  for (const DroneConfig& c : drone_configs()) {
    if (q(c.name) != name) continue;
    // Each property of the schema a recorded change, as if set by hand: a list of our own would miss
    // the next property added. Speed last: a larger radius may allow it (check_drone's step limit).
    std::vector<const DroneProperty*> order;
    for (const DroneProperty& p : salsa::drone_schema())
      if (p.spec.name != "max_speed") order.push_back(&p);
    order.push_back(salsa::drone_schema().find("max_speed"));
    for (const DroneProperty* p : order) {
      const DroneSection section = p->section == DroneSection::returning ? DroneSection::energy : p->section;  // one panel
      const ParamPanel* panel = drone_panels()[static_cast<std::size_t>(section)];
      if (panel->value(p->spec.name) != p->get(c)) live_change(group_key("drone." + p->spec.name), p->get(c));
    }
    const bool was = updating_;
    updating_ = true;
    show_drone(c);
    updating_ = was;
    return;
  }
}

void SandboxPage::save_drone_config() {
  bool ok = false;
  const QString name = QInputDialog::getText(this, "Save drone configuration", "Name:", QLineEdit::Normal, "my-drone", &ok);
  if (ok && !name.isEmpty()) save_drone_config_as(name);
}

std::string SandboxPage::save_drone_config_as(const QString& name) {
  if (const std::string why = name_problem(name.toStdString()); !why.empty()) {
    show_message("drone configuration name: " + q(why));
    return "drone configuration name: " + why;
  }
  // One entry per name: a built-in configuration keeps its values.
  for (const DroneConfig& c : builtin_drone_configs())
    if (q(c.name) == name) {
      show_message("drone configuration name: '" + name + "' is a built-in configuration (allowed: any other name)");
      return last_message_.toStdString();
    }
  QSettings settings;
  json saved = json::object();
  try {
    const auto text = settings.value("drone_configs").toString().toStdString();
    if (!text.empty()) saved = json::parse(text);
  } catch (const std::exception&) {
  }
  json fields = params_json(drone_panel_);
  fields.update(params_json(battery_panel_));
  fields.update(params_json(noise_panel_));
  saved[name.toStdString()] = fields;
  settings.setValue("drone_configs", q(saved.dump()));
  const bool was = updating_;
  updating_ = true;
  if (drone_config_->findText(name) < 0) drone_config_->addItem(name);
  drone_config_->setCurrentText(name);
  updating_ = was;
  show_message("saved drone configuration '" + name + "'", false);
  return {};
}

}  // namespace salsa::gui
