// The sandbox's model boxes: one per model of a test's sections (test_models(): failures, comm, wind and
// any added with add_test_model), built from its declaration. Title and tooltip from its meaning, a
// panel row per field (range, step, unit from its Parameter), values shown with the field's get and
// written into the test's section by name, a change sent live as "<key>.<field>". A model whose section
// alone switches it on (its `given`) has a checkable box: ticking or unticking starts over. Only what
// the declaration cannot say is added by key: the failures' "never" and fail button, the comm note.
#include <QGroupBox>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>
#include <nlohmann/json.hpp>

#include "number_field.hpp"
#include "param_panel.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "sandbox_page.hpp"

namespace salsa::gui {
namespace {

using json = nlohmann::ordered_json;

QString q(const std::string& s) { return QString::fromStdString(s); }

const TestModel* model_named(const std::string& key) {
  for (const TestModel& m : test_models())
    if (m.key == key) return &m;
  return nullptr;
}

/// "comm: a test's communication model": the meaning's first clause (the key when it has none).
QString title_of(const TestModel& m) {
  std::string first = m.meaning.substr(0, m.meaning.find_first_of(".\n"));
  if (const auto paren = first.find(" ("); paren != std::string::npos) first.resize(paren);
  return q(first.empty() ? m.key : first);
}

/// The meaning as one paragraph (its line breaks are a terminal's).
QString tooltip_of(const TestModel& m, bool switched) {
  return q(m.meaning).replace('\n', ' ') +
         (switched ? "\n\nTicked: the test has it (ticking or unticking starts over). Its numbers change live, recorded in the timeline."
                   : "\n\nIts numbers change live, recorded in the timeline (kept by Save as test); all at their defaults, the test has none.");
}

}  // namespace

QGroupBox* SandboxPage::model_box(const std::string& key) const {
  for (const ModelBox& b : model_boxes_)
    if (b.key == key) return b.box;
  return nullptr;
}

ParamPanel* SandboxPage::model_panel(const std::string& key) const {
  for (const ModelBox& b : model_boxes_)
    if (b.key == key) return b.panel;
  return nullptr;
}

void SandboxPage::build_model_boxes(QVBoxLayout* column) {
  for (const TestModel& m : test_models()) {
    if (m.fields.empty()) continue;  // its settings are elsewhere (the drone's): nothing to edit here
    const bool switched = static_cast<bool>(m.given);
    auto* box = new QGroupBox(title_of(m));
    box->setObjectName(q(m.key));
    box->setCheckable(switched);
    box->setChecked(false);
    box->setToolTip(tooltip_of(m, switched));
    auto* panel = new ParamPanel;
    panel->setObjectName(q(m.key + "_panel"));
    Parameters rows;
    for (const ModelField& f : m.fields) rows.push_back(f.spec);
    panel->set_schema(rows);
    (new QVBoxLayout(box))->addWidget(panel);
    column->addWidget(box);
    model_boxes_.push_back({m.key, box, panel});
    connect(box, &QGroupBox::toggled, this, [this](bool) {
      if (!updating_) schedule_reload();
    });
    connect(panel, &ParamPanel::changed, this, [this, key = m.key](const std::string& name, double v) {
      if (updating_) return;
      // A model whose numbers may not change while it is off takes one then as a new start state.
      const TestModel* model = model_named(key);
      const auto now = engine_.current_test();
      if (model && !model->changes_while_off && now && model->in_use && !model->in_use(*now)) schedule_reload();
      else live_change(key + "." + name, v);
    });
  }

  // What the declarations cannot say. Failures: 0 means never; one drone failed by hand, recorded.
  if (ParamPanel* failures = model_panel("failures")) {
    for (const Parameter& p : failures->schema()) failures->spin_box(p.name)->set_special_text("never");
    fail_ = new QPushButton("Fail the inspected drone");
    fail_->setObjectName("fail_drone");
    fail_->setToolTip("click a drone, then this: it fails now (fail.drone), stopping where it is");
    fail_->setEnabled(false);
    model_box("failures")->layout()->addWidget(fail_);
    connect(fail_, &QPushButton::clicked, this, [this] {
      if (fail_target_) live_change("fail.drone", *fail_target_);
    });
  }
  // Comm: why the view may show no links (only messages are drawn, and only a behavior that broadcasts sends).
  if (QGroupBox* comm = model_box("comm")) {
    comm_note_ = new QLabel;
    comm_note_->setObjectName("comm_note");
    comm_note_->setWordWrap(true);
    comm_note_->setStyleSheet("color: palette(mid)");
    comm->layout()->addWidget(comm_note_);
  }
}

void SandboxPage::show_models(const TestSpec& t) {
  for (const ModelBox& b : model_boxes_) {
    const TestModel* m = model_named(b.key);
    if (!m) continue;
    if (b.box->isCheckable()) b.box->setChecked(m->in_use && m->in_use(t));
    for (const ModelField& f : m->fields) b.panel->set_value(f.spec.name, f.get(t));
  }
}

void SandboxPage::models_json(json& j) const {
  const TestSpec blank;  // a test without any model's section
  for (const ModelBox& b : model_boxes_) {
    const TestModel* m = model_named(b.key);
    if (!m) continue;
    // Keys of the section read elsewhere (the wind's field plugin) are kept from the file.
    json section = json::object();
    if (j.contains(m->key) && j[m->key].is_object())
      for (const std::string& k : m->other_keys)
        if (j[m->key].contains(k)) section[k] = j[m->key][k];
    const bool others = !section.empty();
    j.erase(m->key);
    bool set = false;  // a number not as a test without the section has it
    for (const ModelField& f : m->fields) {
      const double v = b.panel->value(f.spec.name);
      set = set || v != f.get(blank);
      json* at = &section;  // "gusts.strength" nested as {"gusts": {"strength": ...}}
      for (std::size_t start = 0, dot; (dot = f.spec.name.find('.', start)) != std::string::npos; start = dot + 1)
        at = &(*at)[f.spec.name.substr(start, dot - start)];
      (*at)[f.spec.name.substr(f.spec.name.rfind('.') + 1)] =
          f.flag ? json(v != 0) : f.spec.is_integer() ? json(static_cast<std::int64_t>(v)) : json(v);
    }
    if (b.box->isCheckable() ? b.box->isChecked() : set || others) j[m->key] = section;
  }
}

}  // namespace salsa::gui
