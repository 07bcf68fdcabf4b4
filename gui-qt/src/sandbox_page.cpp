#include "sandbox_page.hpp"

#include <QAbstractSpinBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QScrollArea>
#include <QSettings>
#include <QSpinBox>
#include <QToolButton>
#include <QVBoxLayout>
#include <algorithm>
#include <charconv>
#include <fstream>
#include <nlohmann/json.hpp>

#include "live_charts.hpp"
#include "param_panel.hpp"
#include "recorder.hpp"
#include "save_checked.hpp"
#include "salsa/core/files/names.hpp"

namespace salsa::gui {
namespace {

using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

/// The comm model's and the wind's numbers as panel rows (each declared once, in its schema).
Parameters comm_parameters() {
  Parameters out;
  for (const CommField& f : comm_schema()) out.push_back(f.spec);
  return out;
}
Parameters wind_parameters() {
  Parameters out;
  for (const WindProperty& p : wind_schema()) out.push_back(p.spec);
  return out;
}

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

double drone_value(const DroneConfig& d, const std::string& name) { return find_drone_property(name)->get(d); }

// The sandbox's first scene: a small forest, enough drones and trees to see the behavior work.
constexpr const char* first_test = R"({"name": "sandbox", "behavior": "pheromone_avoidance", "drones": 20,
  "map": {"name": "forest", "params": {"size": 500}}, "targets": {"kind": "tree", "count": 500},
  "time": 3600, "seed": 1})";

/// The map box's entry while a map file is in use (not a map plugin's name: names have no spaces).
const QString map_file_prefix = "map file: ";

}  // namespace

SandboxPage::SandboxPage(std::shared_ptr<const PluginHost> host, QWidget* parent)
    : QWidget(parent), host_(std::move(host)), engine_(host_) {
  view_ = new SwarmView;
  connect(view_, &SwarmView::drone_clicked, this, [this](std::optional<std::uint32_t> id) { engine_.select(id); });
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(view_);
  build_controls();
  connect(&timer_, &QTimer::timeout, this, &SandboxPage::refresh);
  timer_.start(16);
  fps_since_ = slow_refresh_ = Clock::now();
}

SandboxPage::~SandboxPage() {
  if (recorder_) recorder_->stop();
}

std::vector<QLabel*> SandboxPage::status_labels() const {
  return {status_time_, status_speed_, status_fps_, status_found_, status_inexact_};
}

void SandboxPage::set_active(bool active) {
  active_ = active;
  for (QLabel* l : {status_time_, status_speed_, status_fps_, status_found_}) l->setVisible(active);
  if (!active) status_inexact_->hide();
}

std::string SandboxPage::open_test_spec(const TestSpec& test) {
  const TestSpec previous = file_base_;
  file_base_ = test;
  if (const std::string why = load(file_base_); !why.empty()) {
    file_base_ = previous;
    return why;
  }
  if (!test.changes.empty())
    show_message(QString("'%1': its %2 timed changes apply as it runs, as in salsa run").arg(q(test.name)).arg(test.changes.size()), false);
  return {};
}

void SandboxPage::fill_plugin_lists() {
  const bool was = updating_;
  updating_ = true;
  auto refill = [](QComboBox* box, const QStringList& names) {
    const QString keep = box->currentText();
    box->clear();
    box->addItems(names);
    if (box->findText(keep) < 0 && !keep.isEmpty()) box->addItem(keep);  // still running, though gone from the folders
    box->setCurrentText(keep);
  };
  QStringList behaviors, maps, kinds;
  for (const auto& e : host_->behaviors()) behaviors << q(e.factory.name);
  for (const auto& e : host_->maps())
    if (e.factory.name != "json") maps << q(e.factory.name);
  for (const auto& e : host_->target_kinds()) kinds << q(e.factory.name);
  refill(behavior_, behaviors);
  refill(map_, maps);
  refill(target_kind_, kinds);
  updating_ = was;
}

void SandboxPage::use_plugins(std::shared_ptr<const PluginHost> host, const QStringList& rebuilt) {
  host_ = std::move(host);
  fill_plugin_lists();
  // The running behaviors (of any group) whose files were rebuilt: each group running one reloads.
  std::vector<std::string> reload;
  std::string what;  // "behavior 'a' from /x/liba.so", for the messages
  for (const std::string& running : engine_.behavior_names()) {
    const auto& all = host_->behaviors();
    if (std::find(reload.begin(), reload.end(), running) != reload.end() ||
        std::none_of(all.begin(), all.end(), [&](const auto& e) { return e.factory.name == running; }))
      continue;
    const std::string file = host_->behavior(running).plugin().file.string();
    if (!rebuilt.contains(q(file))) continue;
    reload.push_back(running);
    what += (what.empty() ? "behavior '" : ", behavior '") + running + "' from " + file;
  }
  const bool reloading = !reload.empty();
  pending_.push_back({engine_.use_plugins(host_, std::move(reload)), [this, reloading, what](const std::string& why) {
                        if (!why.empty()) return show_message(q(what + " was not reloaded: " + why));
                        if (!reloading) return show_message(QString("plugins rescanned: %1 files").arg(host_->plugins().size()), false);
                        if (auto t = engine_.current_test()) {
                          loaded_ = *t;
                          show_test(*t);  // the new code's parameters
                        }
                        show_message(q("reloaded " + what + ": the simulation goes on with the new code"), false);
                      }});
}

// ---------------------------------------------------------------- controls

void SandboxPage::build_controls() {
  auto* panel = new QWidget;
  auto* column = new QVBoxLayout(panel);

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
  targets_ = new QSpinBox;
  targets_->setObjectName("targets");
  targets_->setRange(0, 10'000'000);
  targets_->setSingleStep(100);
  targets_->setKeyboardTracking(false);  // one new world per edit, not one per keystroke
  form->addRow("targets", targets_);
  // A line, not a spin box: a QSpinBox holds an int, and seeds go to 2^53.
  seed_ = new QLineEdit;
  seed_->setObjectName("seed");
  seed_->setToolTip(QString("the test's seed: a whole number in [0, %1] (Enter applies it)").arg(max_sandbox_seed));
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
  drones_ = new QSpinBox;
  drones_->setObjectName("drones");
  drones_->setRange(1, 1'000'000);
  drones_->setKeyboardTracking(false);
  drones_->setToolTip("drones added at the (chosen group's) base, or its highest ids removed");
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
  battery_toggle_ = new QToolButton;
  battery_toggle_->setObjectName("battery_toggle");
  battery_toggle_->setText("Battery and power model");
  battery_toggle_->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
  battery_toggle_->setArrowType(Qt::RightArrow);
  battery_toggle_->setCheckable(true);
  battery_toggle_->setAutoRaise(true);
  battery_toggle_->setToolTip("battery capacity (0 Wh: no battery model), the rotary-wing power model of Zeng, Xu & Zhang (2019) "
                              "and charging at the base");
  live_form->addWidget(battery_toggle_);
  battery_panel_ = new ParamPanel;
  battery_panel_->setObjectName("battery_panel");
  battery_panel_->set_schema(drone_schema(DroneSection::energy));
  // 0 means "off" for these two: say so rather than show "0.0 Wh".
  qobject_cast<QDoubleSpinBox*>(battery_panel_->spin_box("battery_capacity"))->setSpecialValueText("none");
  qobject_cast<QDoubleSpinBox*>(battery_panel_->spin_box("charge_power"))->setSpecialValueText("no charging");
  battery_panel_->hide();
  live_form->addWidget(battery_panel_);
  // Sensor noise, off (all 0) by default: folded away likewise.
  noise_toggle_ = new QToolButton;
  noise_toggle_->setObjectName("noise_toggle");
  noise_toggle_->setText("Sensor noise");
  noise_toggle_->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
  noise_toggle_->setArrowType(Qt::RightArrow);
  noise_toggle_->setCheckable(true);
  noise_toggle_->setAutoRaise(true);
  noise_toggle_->setToolTip("noise on the drone's own position, its neighbours and obstacle rays; missed targets and false "
                            "detections (all 0: perfect sensors)");
  live_form->addWidget(noise_toggle_);
  noise_panel_ = new ParamPanel;
  noise_panel_->setObjectName("noise_panel");
  noise_panel_->set_schema(drone_schema(DroneSection::noise));
  noise_panel_->hide();
  live_form->addWidget(noise_panel_);
  auto* fine = new QLabel("Sliders: click one, then the arrow keys move it one fine step; ranges over decades are logarithmic.");
  fine->setWordWrap(true);
  fine->setStyleSheet("color: palette(mid)");
  live_form->addWidget(fine);
  column->addWidget(live);

  // Failures: rates for every drone of every group, and one drone failed by hand; recorded like the rest.
  auto* failures = new QGroupBox("Failures (live, recorded)");
  auto* failure_form = new QFormLayout(failures);
  auto mtbf_box = [](const char* name, const QString& tip) {
    auto* box = new QDoubleSpinBox;
    box->setObjectName(name);
    box->setRange(0, 1e9);  // as check_change allows
    box->setDecimals(0);
    box->setSingleStep(60);
    box->setSuffix(" s");
    box->setSpecialValueText("never");
    box->setKeyboardTracking(false);
    box->setToolTip(tip + " (allowed: [0, 1e9] s; 0: never)");
    return box;
  };
  drone_mtbf_ = mtbf_box("drone_mtbf", "mean time to failure of a whole drone: each drone's failure time is drawn from the seed");
  camera_mtbf_ = mtbf_box("camera_mtbf", "mean time to failure of a drone's camera: it flies on, finding nothing");
  failure_form->addRow("drone MTBF", drone_mtbf_);
  failure_form->addRow("camera MTBF", camera_mtbf_);
  fail_ = new QPushButton("Fail the inspected drone");
  fail_->setObjectName("fail_drone");
  fail_->setToolTip("click a drone, then this: it fails now (fail.drone), stopping where it is");
  fail_->setEnabled(false);
  failure_form->addRow(fail_);
  column->addWidget(failures);

  // Communication: turning it on or off is a new start state; its fields change live, recorded.
  comm_box_ = new QGroupBox("Communication (fields live, recorded)");
  comm_box_->setObjectName("comm");
  comm_box_->setCheckable(true);
  comm_box_->setChecked(false);
  comm_box_->setToolTip("messages between drones (docs/test-format.md#communication); off: nobody hears anybody");
  comm_panel_ = new ParamPanel;
  comm_panel_->set_schema(comm_parameters());
  (new QVBoxLayout(comm_box_))->addWidget(comm_panel_);
  column->addWidget(comm_box_);

  // Wind, the same way: on or off starts over (the test's field plugin, if any, is kept), its numbers live.
  wind_box_ = new QGroupBox("Wind (numbers live, recorded)");
  wind_box_->setObjectName("wind");
  wind_box_->setCheckable(true);
  wind_box_->setChecked(false);
  wind_box_->setToolTip("constant wind and gusts; a drone's max speed and power are through the air (docs/test-format.md#wind). "
                        "Ticked with no wind set, it starts as 3 m/s along +x");
  wind_panel_ = new ParamPanel;
  wind_panel_->set_schema(wind_parameters());
  (new QVBoxLayout(wind_box_))->addWidget(wind_panel_);
  column->addWidget(wind_box_);

  auto* run = new QGroupBox("Run");
  auto* run_layout = new QVBoxLayout(run);
  auto* buttons = new QHBoxLayout;
  run_button_ = new QPushButton("Start");
  auto* step_button = new QPushButton("Step");
  auto* reset_button = new QPushButton("Reset");
  for (auto* b : {run_button_, step_button, reset_button}) buttons->addWidget(b);
  run_layout->addLayout(buttons);
  auto* speed = new QHBoxLayout;
  pacing_ = new QComboBox;
  pacing_->setObjectName("pacing");
  pacing_->addItems({"real time", "steps per frame", "larger time step ×", "as fast as possible"});
  pacing_->setToolTip("real time; N exact steps per frame; a step N times longer (fast, inexact); or flat out");
  pacing_amount_ = new QSpinBox;
  pacing_amount_->setObjectName("pacing_amount");
  pacing_amount_->setRange(1, 1000);
  pacing_amount_->setValue(4);
  pacing_amount_->setKeyboardTracking(false);
  pacing_amount_->setEnabled(false);
  speed->addWidget(pacing_, 1);
  speed->addWidget(pacing_amount_);
  run_layout->addLayout(speed);
  column->insertWidget(0, run);  // first: the buttons used most stay in sight
  column->addStretch();

  for (QWidget* input : panel->findChildren<QWidget*>())
    if (qobject_cast<QAbstractSpinBox*>(input) || qobject_cast<QComboBox*>(input)) wheel_scrolls_unless_focused(input);
  auto* scroll = new QScrollArea;
  scroll->setWidget(panel);
  scroll->setWidgetResizable(true);
  scroll->setMinimumWidth(340);
  controls_ = scroll;

  charts_ = new LiveCharts;
  inspector_ = new QPlainTextEdit;
  inspector_->setReadOnly(true);
  inspector_->setPlaceholderText("Click a drone to inspect it.");
  inspector_->setMaximumHeight(220);

  status_time_ = new QLabel;
  status_speed_ = new QLabel;
  status_fps_ = new QLabel;
  status_found_ = new QLabel;
  status_inexact_ = new QLabel("inexact: larger time step");
  status_inexact_->setStyleSheet("color: #b00020; font-weight: bold");
  status_inexact_->hide();

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
  connect(targets_, &QSpinBox::valueChanged, this, reload);
  connect(physics_, &QComboBox::currentTextChanged, this, reload);
  connect(seed_, &QLineEdit::editingFinished, this, &SandboxPage::seed_edited);
  connect(open_map_button, &QPushButton::clicked, this, &SandboxPage::ask_open_map);
  connect(group_, &QComboBox::currentTextChanged, this, [this](const QString& name) {
    if (updating_ || name.isEmpty()) return;
    group_name_ = name.toStdString();
    if (auto t = engine_.current_test()) show_test(*t);
  });
  connect(drones_, &QSpinBox::valueChanged, this, [this](int n) {
    if (!updating_) live_change(group_key("drones"), n);
  });
  connect(behavior_panel_, &ParamPanel::changed, this, [this](const std::string& name, double v) {
    if (!updating_) live_change(group_key("behavior.params." + name), v);
  });
  for (ParamPanel* drone : drone_panels())
    connect(drone, &ParamPanel::changed, this, [this](const std::string& name, double v) {
      if (!updating_) live_change(group_key("drone." + name), v);
    });
  connect(battery_toggle_, &QToolButton::toggled, this, [this](bool open) {
    battery_panel_->setVisible(open);
    battery_toggle_->setArrowType(open ? Qt::DownArrow : Qt::RightArrow);
  });
  connect(noise_toggle_, &QToolButton::toggled, this, [this](bool open) {
    noise_panel_->setVisible(open);
    noise_toggle_->setArrowType(open ? Qt::DownArrow : Qt::RightArrow);
  });
  connect(drone_mtbf_, &QDoubleSpinBox::valueChanged, this, [this](double v) {
    if (!updating_) live_change("failures.drone_mtbf", v);
  });
  connect(camera_mtbf_, &QDoubleSpinBox::valueChanged, this, [this](double v) {
    if (!updating_) live_change("failures.camera_mtbf", v);
  });
  connect(comm_box_, &QGroupBox::toggled, this, [this](bool) {
    if (!updating_) schedule_reload();
  });
  connect(comm_panel_, &ParamPanel::changed, this, [this](const std::string& name, double v) {
    if (!updating_) live_change("comm." + name, v);
  });
  connect(wind_box_, &QGroupBox::toggled, this, [this](bool on) {
    if (updating_) return;
    // A wind of zero is no wind: ticked over all zeros, it starts as a 3 m/s breeze along +x to edit.
    const bool calm = std::all_of(wind_schema().begin(), wind_schema().end(), [&](const WindProperty& p) {
      return p.spec.name == "gusts.time_scale" || wind_panel_->value(p.spec.name) == 0;
    });
    if (on && calm) wind_panel_->set_value("velocity.x", 3);
    schedule_reload();
  });
  connect(wind_panel_, &ParamPanel::changed, this, [this](const std::string& name, double v) {
    if (!updating_) live_change("wind." + name, v);
  });
  connect(fail_, &QPushButton::clicked, this, [this] {
    if (fail_target_) live_change("fail.drone", *fail_target_);
  });
  connect(drone_config_, &QComboBox::activated, this, [this](int) { apply_drone_config(drone_config_->currentText()); });
  connect(save_config, &QPushButton::clicked, this, &SandboxPage::save_drone_config);
  connect(run_button_, &QPushButton::clicked, this, &SandboxPage::toggle_run);
  connect(step_button, &QPushButton::clicked, this, &SandboxPage::step);
  connect(reset_button, &QPushButton::clicked, this, &SandboxPage::reset);
  connect(pacing_, &QComboBox::currentIndexChanged, this, &SandboxPage::set_pacing);
  connect(pacing_amount_, &QSpinBox::valueChanged, this, &SandboxPage::set_pacing);
}

void SandboxPage::show_message(const QString& text, bool error) {
  last_message_ = text;
  Q_EMIT message(text, error);
  if (!error) return;
  // Not modal-blocking: the simulation and the view go on while the message is up.
  auto* box = new QMessageBox(QMessageBox::Warning, "salsa", text, QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
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
    for (const Parameter& p : panel->schema()) find_drone_property(p.name)->set(d, panel->value(p.name));
  group["drone"] = drone_json(d);
  group["drones"] = drones_->value();
  j.erase("failures");
  if (drone_mtbf_->value() > 0 || camera_mtbf_->value() > 0)
    j["failures"] = {{"drone_mtbf", drone_mtbf_->value()}, {"camera_mtbf", camera_mtbf_->value()}};
  j.erase("comm");
  if (comm_box_->isChecked()) {
    json comm = json::object();
    for (const CommField& f : comm_schema()) {
      const double v = comm_panel_->value(f.spec.name);
      comm[f.spec.name] = f.flag ? json(v != 0) : json(v);
    }
    j["comm"] = comm;
  }
  const json field = j.contains("wind") && j["wind"].contains("field") ? j["wind"]["field"] : json();
  j.erase("wind");
  if (wind_box_->isChecked()) {
    Wind w;
    for (const WindProperty& p : wind_schema()) p.set(w, wind_panel_->value(p.spec.name));
    j["wind"] = {{"velocity", {w.velocity.x, w.velocity.y}}, {"gusts", {{"strength", w.gust_strength}, {"time_scale", w.gust_time_scale}}}};
    if (!field.is_null()) j["wind"]["field"] = field;
  }
  if (!map_file_.isEmpty()) j["map"] = {{"file", map_file_.toStdString()}};
  else j["map"] = {{"name", map_->currentText().toStdString()}, {"params", params_json(map_panel_)}};
  const bool same_kind = target_kind_->currentText().toStdString() == file_base_.target.name;
  j["targets"] = {{"kind", target_kind_->currentText().toStdString()}, {"count", targets_->value()}};
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

std::string SandboxPage::load(const TestSpec& test) {
  reload_due_ = false;  // this load supersedes an edit still waiting
  const std::string why = engine_.load(test).get();  // building a world takes a moment; the user asked for it
  if (!why.empty()) {
    show_message(q(why));
    if (loaded_) show_test(*engine_.current_test());  // the controls go back to what runs
    return why;
  }
  loaded_ = test;
  past_time_told_ = false;
  show_test(test);
  view_->fit();
  return {};
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
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || v > max_sandbox_seed) {
    const bool was = updating_;
    updating_ = true;
    seed_->setText(QString::number(seed_value_));
    updating_ = was;
    show_message(QString("seed: \"%1\" is not a seed (allowed: whole number in [0, %2])").arg(q(text)).arg(max_sandbox_seed));
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
  targets_->setValue(static_cast<int>(t.targets));
  seed_value_ = t.seed;
  seed_->setText(QString::number(t.seed));
  physics_->setCurrentText(t.physics == PhysicsMode::light ? "light" : "box2d");
  drones_->setValue(static_cast<int>(group.drones));
  drone_config_->clear();
  for (const DroneConfig& c : drone_configs()) drone_config_->addItem(q(c.name));
  if (drone_config_->findText(q(group.drone.name)) < 0) drone_config_->addItem(q(group.drone.name));
  drone_config_->setCurrentText(q(group.drone.name));
  for (ParamPanel* panel : drone_panels())
    for (const Parameter& p : panel->schema()) panel->set_value(p.name, drone_value(group.drone, p.name));
  if (group.drone.battery_capacity > 0) battery_toggle_->setChecked(true);  // a battery in use is shown
  if (section_in_use(group.drone, DroneSection::noise)) noise_toggle_->setChecked(true);  // so is noise
  drone_mtbf_->setValue(t.failures.drone_mtbf);
  camera_mtbf_->setValue(t.failures.camera_mtbf);
  comm_box_->setChecked(t.comm.on);
  for (const CommField& f : comm_schema()) comm_panel_->set_value(f.spec.name, f.get(t.comm));
  wind_box_->setChecked(t.has_wind());
  for (const WindProperty& p : wind_schema()) wind_panel_->set_value(p.spec.name, p.get(t.wind));
  updating_ = was;
}

std::string SandboxPage::open_test(const QString& file) {
  std::vector<TestSpec> tests;
  try {
    tests = load_tests(file.toStdString(), *host_);
  } catch (const std::exception& e) {
    show_message(q(e.what()));
    return e.what();
  }
  if (tests.empty()) {
    show_message(file + ": holds no test");
    return (file + ": holds no test").toStdString();
  }
  const TestSpec previous = file_base_;
  file_base_ = tests.front();
  if (const std::string why = load(tests.front()); !why.empty()) {
    file_base_ = previous;
    return why;
  }
  if (tests.size() > 1) show_message(QString("%1 holds %2 tests: the first, '%3', is loaded").arg(file).arg(tests.size()).arg(q(tests.front().name)), false);
  if (!tests.front().changes.empty())
    show_message(QString("%1: its %2 timed changes apply as it runs, as in salsa run").arg(file).arg(tests.front().changes.size()), false);
  return {};
}

std::string SandboxPage::open_map(const QString& file) {
  try {
    load_map_file(file.toStdString(), *host_, loaded_ ? loaded_->groups[0].drone.radius : 1);  // the CLI's checks, before anything changes
  } catch (const std::exception& e) {
    show_message(q(e.what()));
    return e.what();
  }
  const QString previous = map_file_;
  map_file_ = QFileInfo(file).absoluteFilePath();
  std::string why;
  const auto spec = spec_from_controls(&why);
  if (!spec || !(why = load(*spec)).empty()) {
    map_file_ = previous;
    if (!spec) show_message(q(why));
    return why;
  }
  return {};
}

std::string SandboxPage::save_test(const QString& file) {
  std::string why;
  auto test = engine_.as_test(&why);
  if (!test) {
    show_message(q(why));
    return why;
  }
  // The file's name names the test (and its output folder), when it is a valid name.
  const std::string stem = QFileInfo(file).completeBaseName().toStdString();
  if (test_name_problem(stem).empty()) test->name = stem;
  std::ofstream out(file.toStdString(), std::ios::binary);
  out << resolved_json(*test, *host_);
  out.close();
  if (!out) {
    why = file.toStdString() + ": cannot write the test";
    show_message(q(why));
    return why;
  }
  show_message(QString("saved %1: %2 s with %3 live changes; replay it with `salsa run %1`")
                   .arg(file).arg(test->time).arg(test->changes.size()), false);
  return {};
}

std::string SandboxPage::save_screenshot(const QString& file) {
  QString error;
  if (!save_png(view_->screenshot(), file, &error)) {
    show_message(error);
    return error.toStdString();
  }
  show_message("saved " + file, false);
  return {};
}

void SandboxPage::ask_open_test() {
  const QString f = QFileDialog::getOpenFileName(this, "Open a test", {}, "Tests (*.json)");
  if (!f.isEmpty()) open_test(f);
}

void SandboxPage::ask_open_map() {
  const QString f = QFileDialog::getOpenFileName(this, "Open a map", {}, "JSON maps (*.json)");
  if (!f.isEmpty()) open_map(f);
}

void SandboxPage::ask_save_test() {
  std::string why;
  if (!engine_.as_test(&why)) return show_message(q("nothing to save as a test: " + why));  // before a name is asked for
  const QString f = ask_save_file(this, "Save as test", "sandbox.json", "Tests (*.json)", [](const QString& file) {
    const std::string stem = QFileInfo(file).completeBaseName().toStdString();
    return test_name_problem(stem).empty() ? std::string() : "the file's name names the test: " + test_name_problem(stem);
  });
  if (!f.isEmpty()) save_test(f);
}

void SandboxPage::ask_screenshot() {
  const QString f = ask_save_file(this, "Screenshot", "salsa.png", "PNG images (*.png)", [](const QString& file) {
    return file.endsWith(".png", Qt::CaseInsensitive) ? std::string() : "a screenshot is a PNG file: its name ends in .png";
  });
  if (!f.isEmpty()) save_screenshot(f);
}

// ---------------------------------------------------------------- live changes and running

void SandboxPage::live_change(const std::string& key, double value) {
  pending_.push_back({engine_.set(key, value), [this](const std::string& why) {
                        if (why.empty()) return;
                        show_message(q(why));
                        if (auto t = engine_.current_test()) show_test(*t);  // back to what runs
                      }});
}

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
    order.push_back(find_drone_property("max_speed"));
    for (const DroneProperty* p : order) {
      const ParamPanel* panel = drone_panels()[static_cast<std::size_t>(p->section)];
      if (panel->value(p->spec.name) != p->get(c)) live_change(group_key("drone." + p->spec.name), p->get(c));
    }
    const bool was = updating_;
    updating_ = true;
    for (ParamPanel* panel : drone_panels())
      for (const Parameter& p : panel->schema()) panel->set_value(p.name, drone_value(c, p.name));
    updating_ = was;
    return;
  }
}

void SandboxPage::save_drone_config() {
  bool ok = false;
  const QString name = QInputDialog::getText(this, "Save drone configuration", "Name:", QLineEdit::Normal, "my-drone", &ok);
  if (!ok || name.isEmpty()) return;
  if (const std::string why = name_problem(name.toStdString()); !why.empty()) {
    show_message("drone configuration name: " + q(why));
    return;
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
}

void SandboxPage::start() {
  engine_.start();
  run_button_->setText("Pause");
}
void SandboxPage::pause() {
  engine_.pause();
  run_button_->setText("Start");
}
void SandboxPage::toggle_run() {
  const auto snap = engine_.snapshot();
  if (snap->state == RunState::running) pause();
  else start();
}
void SandboxPage::step() {
  run_button_->setText("Start");
  pending_.push_back({engine_.step_once(), [this](const std::string& why) {
                        if (!why.empty()) show_message(q(why));
                      }});
}
void SandboxPage::reset() {
  run_button_->setText("Start");
  past_time_told_ = false;
  pending_.push_back({engine_.reset(), [this](const std::string& why) {
                        if (!why.empty()) show_message(q(why));
                        else if (loaded_) show_test(*loaded_);
                      }});
}

void SandboxPage::set_pacing() {
  Pacing p;
  const int mode = pacing_->currentIndex();
  p.mode = mode == 0 ? Pacing::real_time : mode == 1 ? Pacing::steps_per_frame : mode == 2 ? Pacing::real_time : Pacing::fastest;
  pacing_amount_->setEnabled(mode == 1 || mode == 2);
  if (mode == 1) p.steps = pacing_amount_->value();
  if (mode == 2) {  // the larger step runs as fast as it can: it is there for speed
    p.mode = Pacing::fastest;
    p.dt_factor = pacing_amount_->value();
  }
  pending_.push_back({engine_.set_pacing(p), [this](const std::string& why) {
                        if (why.empty()) return;
                        show_message(q(why));
                        const bool was = updating_;
                        updating_ = true;
                        pacing_->setCurrentIndex(0);
                        pacing_amount_->setEnabled(false);
                        updating_ = was;
                        engine_.set_pacing({});
                      }});
}

void SandboxPage::toggle_recording() {
  if (recorder_) {
    recorder_->stop();
    const int frames = recorder_->frames();
    QString error;
    const QString video = recorder_->make_video(&error);
    recorder_.reset();
    Q_EMIT recording_changed(false);
    show_message(video.isEmpty() ? QString("recorded %1 frames; %2").arg(frames).arg(error)
                                 : QString("recorded %1 frames: %2").arg(frames).arg(video),
                 false);
    return;
  }
  const QString folder = QFileDialog::getExistingDirectory(this, "Record PNG frames into");
  if (folder.isEmpty()) return;
  bool ok = false;
  const double interval = QInputDialog::getDouble(this, "Recording", "One frame every (simulated seconds):", 0.1, 0.001, 3600, 3, &ok);
  if (!ok) return;
  QSize size = view_->size();
  size = QSize(size.width() / 2 * 2, size.height() / 2 * 2);  // even: video encoders need it
  recorder_ = std::make_unique<Recorder>(engine_, folder, interval, size, view_->options(), view_->world_to_px());
  recorder_->start();
  Q_EMIT recording_changed(true);
  show_message(QString("recording a frame every %1 s of simulated time into %2").arg(interval).arg(folder), false);
}

// ---------------------------------------------------------------- showing

QString SandboxPage::inspector_text() const { return inspector_->toPlainText(); }

void SandboxPage::poll() {
  for (std::size_t i = 0; i < pending_.size();) {
    if (pending_[i].answer.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      ++i;
      continue;
    }
    Pending done = std::move(pending_[i]);
    pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(i));
    done.then(done.answer.get());
  }
  if (reload_due_) reload_from_controls();
  // A change of the timeline applied (the test's own, at its time): the controls show what runs now.
  if (const auto snap = engine_.snapshot(); loaded_ && snap->changes_applied != changes_shown_) {
    changes_shown_ = snap->changes_applied;
    if (auto t = engine_.current_test()) show_test(*t);
  }
}

void SandboxPage::refresh() {
  poll();
  auto snap = engine_.snapshot();
  if (snap != shown_) {
    shown_ = snap;
    view_->show_snapshot(snap);
    ++frames_;
  }
  // The test's time: the sandbox pauses there once and says so; Start runs on past it, marked below.
  const double end = loaded_ ? loaded_->time : 0;
  const bool past = loaded_ && snap->time >= end - 1e-9 && snap->test_name == loaded_->name;
  if (past && !past_time_told_ && snap->state == RunState::running) {
    past_time_told_ = true;
    pause();
    show_message(QString("paused at t = %1 s: the test's time is %2 s (Start runs on past it; Save as test keeps the time reached)")
                     .arg(snap->time, 0, 'f', 1).arg(end),
                 false);
  }
  const auto now = Clock::now();
  if (now - slow_refresh_ < std::chrono::milliseconds(250)) return;  // text and plots: a few times a second
  const double since = std::chrono::duration<double>(now - fps_since_).count();
  if (since >= 1) {
    fps_ = frames_ / since;
    frames_ = 0;
    fps_since_ = now;
  }
  slow_refresh_ = now;
  charts_->show_rows(snap->stats);
  status_time_->setText(past ? QString("t = %1 s, past the test's %2 s").arg(snap->time, 0, 'f', 1).arg(end)
                             : QString("t = %1 s").arg(snap->time, 0, 'f', 1));
  status_time_->setStyleSheet(past ? "color: #b00020; font-weight: bold" : "");
  status_speed_->setText(QString("%1× real time").arg(snap->speed, 0, 'f', snap->speed < 10 ? 2 : 0));
  status_fps_->setText(QString("%1 FPS").arg(fps_, 0, 'f', 0));
  const std::size_t targets = snap->found.size();
  status_found_->setText(targets ? QString("found %1 / %2 (%3 %)").arg(snap->targets_found).arg(targets)
                                       .arg(100.0 * static_cast<double>(snap->targets_found) / static_cast<double>(targets), 0, 'f', 1)
                                 : QString("no targets"));
  status_inexact_->setVisible(snap->inexact && active_);
  if (snap->state == RunState::failed && snap->error != last_error_shown_) {
    last_error_shown_ = snap->error;
    run_button_->setText("Start");
    show_message(q(snap->error));
  }
  if (snap->state != RunState::running && run_button_->text() == "Pause") run_button_->setText("Start");
  // The fail button names the inspected drone while it flies.
  fail_target_.reset();
  if (snap->selected && snap->status_of(snap->selected->id) == DroneStatus::flying) fail_target_ = snap->selected->id;
  fail_->setEnabled(fail_target_ && snap->state != RunState::failed);
  fail_->setText(fail_target_ ? QString("Fail drone %1").arg(*fail_target_) : QString("Fail the inspected drone"));
  if (snap->selected) {
    const Inspection& in = *snap->selected;
    QString text = QString("drone %1").arg(in.id);
    if (snap->groups.size() > 1) text += QString(" of group %1").arg(q(in.group));
    if (in.fleet) {
      text += QString(": %1\n").arg(q(in.status));
      text += in.battery_left ? QString("energy used %1 Wh, battery left %2 %").arg(in.energy_used, 0, 'f', 3).arg(100 * *in.battery_left, 0, 'f', 1)
                              : QString("no battery model");
    }
    text += QString("\nposition (%1, %2) m\nvelocity (%3, %4) m/s, speed %5 m/s\ncommanded (%6, %7) m/s\n")
                .arg(in.position.x, 0, 'f', 2).arg(in.position.y, 0, 'f', 2)
                .arg(in.velocity.x, 0, 'f', 2).arg(in.velocity.y, 0, 'f', 2).arg(in.velocity.length(), 0, 'f', 2)
                .arg(in.commanded.x, 0, 'f', 2).arg(in.commanded.y, 0, 'f', 2);
    text += QString("neighbours (%1 within %2 m):").arg(in.neighbours.size()).arg(snap->drone_of(in.id).detection_range);
    for (std::size_t i = 0; i < std::min<std::size_t>(in.neighbours.size(), 12); ++i) text += QString(" %1").arg(in.neighbours[i]);
    if (in.neighbours.size() > 12) text += " …";
    text += QString("\nobstacle hits: %1").arg(in.hits.size());
    for (const ObstacleHit& h : in.hits) text += QString(" %1 m").arg(h.distance, 0, 'f', 1);
    if (in.perceived)
      text += QString("\nperceived position (%1, %2) m, %3 m off").arg(in.perceived->x, 0, 'f', 2).arg(in.perceived->y, 0, 'f', 2)
                  .arg(distance(*in.perceived, in.position), 0, 'f', 2);
    if (in.air_velocity)
      text += QString("\nair velocity (%1, %2) m/s, air speed %3 m/s").arg(in.air_velocity->x, 0, 'f', 2).arg(in.air_velocity->y, 0, 'f', 2)
                  .arg(in.air_velocity->length(), 0, 'f', 2);
    if (in.heard) {
      text += QString("\nmessages next step: %1 from").arg(in.heard->size());
      for (std::size_t i = 0; i < std::min<std::size_t>(in.heard->size(), 12); ++i) text += QString(" %1").arg((*in.heard)[i]);
      if (in.heard->size() > 12) text += " …";
    }
    if (!in.memory.empty()) text += "\nmemory: " + q(in.memory);
    inspector_->setPlainText(text);
  } else if (!inspector_->toPlainText().isEmpty()) {
    inspector_->clear();
  }
}

// ---------------------------------------------------------------- settings

void SandboxPage::restore_settings() {
  QSettings settings;
  file_base_ = parse_test(first_test, "sandbox", *host_);
  // The last session's start state, if it still parses with the plugins there are now. If not, say
  // what was replaced and why: a relaunch without its --plugin-dir must not swap behaviors silently.
  const QString last = settings.value("sandbox/test").toString();
  QString replaced;
  if (!last.isEmpty()) {
    try {
      file_base_ = parse_test(last.toStdString(), "last session", *host_);
    } catch (const std::exception& e) {
      std::string behavior;
      try {
        const json b = json::parse(last.toStdString()).at("behavior");  // "name" or {"name": ...}
        behavior = b.is_string() ? b.get<std::string>() : b.at("name").get<std::string>();
      } catch (const std::exception&) {
      }
      replaced = QString("the last session's test (behavior '%1') was not restored: %2; the first scene runs instead "
                         "(start salsa-gui with the same --plugin-dir to get it back)")
                     .arg(q(behavior), q(e.what()));
    }
  }
  if (!load(file_base_).empty()) {
    file_base_ = parse_test(first_test, "sandbox", *host_);
    load(file_base_);
    if (replaced.isEmpty()) replaced = "the last session's test did not load (see the message); the first scene runs instead";
  }
  if (!replaced.isEmpty()) show_message(replaced, false);
}

void SandboxPage::save_settings() {
  QSettings settings;
  if (auto t = engine_.current_test()) {
    t->changes.clear();
    settings.setValue("sandbox/test", q(resolved_json(*t, *host_)));
  }
}

}  // namespace salsa::gui
