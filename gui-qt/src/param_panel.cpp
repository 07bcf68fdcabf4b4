#include "param_panel.hpp"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QSlider>
#include <QSpinBox>
#include <cmath>

#include "salsa/core/drone_config.hpp"

namespace salsa::gui {
namespace {
double step_of(const Parameter& p) { return p.step > 0 ? p.step : (p.max - p.min) / 100; }
int decimals_of(const Parameter& p) {
  const double s = step_of(p);
  return p.is_integer() || s >= 1 ? 0 : std::clamp(static_cast<int>(std::ceil(-std::log10(s))), 1, 6);
}
}  // namespace

ParamPanel::ParamPanel(QWidget* parent) : QWidget(parent), form_(new QFormLayout(this)) {
  form_->setContentsMargins(0, 0, 0, 0);
  form_->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
}

int ParamPanel::to_slider(const Parameter& p, double v) const {
  return static_cast<int>(std::lround((v - p.min) / step_of(p)));
}
double ParamPanel::from_slider(const Parameter& p, int s) const { return std::min(p.max, p.min + s * step_of(p)); }

void ParamPanel::set_schema(const Parameters& schema, const ParameterValues& values) {
  while (form_->rowCount() > 0) form_->removeRow(0);
  rows_.clear();
  schema_ = schema;
  for (std::size_t i = 0; i < schema_.size(); ++i) {
    const Parameter& p = schema_[i];
    auto* field = new QWidget;
    auto* line = new QHBoxLayout(field);
    line->setContentsMargins(0, 0, 0, 0);
    Row row;
    row.slider = new QSlider(Qt::Horizontal);
    row.slider->setRange(0, to_slider(p, p.max));
    row.slider->setObjectName(QString::fromStdString(p.name) + "_slider");
    const QString suffix = p.unit.empty() ? QString() : " " + QString::fromStdString(p.unit);
    if (p.is_integer()) {
      auto* spin = new QSpinBox;
      spin->setRange(static_cast<int>(p.min), static_cast<int>(p.max));
      spin->setSuffix(suffix);
      connect(spin, &QSpinBox::valueChanged, this, [this, i](int v) {
        if (updating_) return;
        show_value(i, v);
        Q_EMIT changed(schema_[i].name, v);
      });
      row.spin = spin;
    } else {
      auto* spin = new QDoubleSpinBox;
      spin->setRange(p.min, p.max);
      spin->setDecimals(decimals_of(p));
      spin->setSingleStep(step_of(p));
      spin->setSuffix(suffix);
      spin->setKeyboardTracking(false);  // one change per edit, not per keystroke
      connect(spin, &QDoubleSpinBox::valueChanged, this, [this, i](double v) {
        if (updating_) return;
        show_value(i, v);
        Q_EMIT changed(schema_[i].name, v);
      });
      row.spin = spin;
    }
    row.spin->setObjectName(QString::fromStdString(p.name));
    row.spin->setMinimumWidth(90);
    connect(row.slider, &QSlider::valueChanged, this, [this, i](int s) {
      if (updating_) return;
      const double v = from_slider(schema_[i], s);
      show_value(i, v);
      Q_EMIT changed(schema_[i].name, v);
    });
    const QString tip = QString::fromStdString(p.description + " (allowed: " + p.range() + ")");
    row.slider->setToolTip(tip);
    row.spin->setToolTip(tip);
    line->addWidget(row.slider, 1);
    line->addWidget(row.spin);
    auto* label = new QLabel(QString::fromStdString(p.name).replace('_', ' '));
    label->setToolTip(tip);
    form_->addRow(label, field);
    rows_.push_back(row);
    show_value(i, values.has(p.name) ? values.get(p.name) : p.value);
  }
}

void ParamPanel::show_value(std::size_t i, double v) {
  const bool was = updating_;
  updating_ = true;
  const Parameter& p = schema_[i];
  rows_[i].slider->setValue(to_slider(p, v));
  if (auto* s = qobject_cast<QSpinBox*>(rows_[i].spin)) s->setValue(static_cast<int>(std::lround(v)));
  if (auto* s = qobject_cast<QDoubleSpinBox*>(rows_[i].spin)) s->setValue(v);
  updating_ = was;
}

void ParamPanel::set_value(const std::string& name, double value) {
  for (std::size_t i = 0; i < schema_.size(); ++i)
    if (schema_[i].name == name) show_value(i, value);
}

double ParamPanel::value(const std::string& name) const {
  for (std::size_t i = 0; i < schema_.size(); ++i)
    if (schema_[i].name == name) {
      if (auto* s = qobject_cast<QSpinBox*>(rows_[i].spin)) return s->value();
      if (auto* s = qobject_cast<QDoubleSpinBox*>(rows_[i].spin)) return s->value();
    }
  return std::nan("");
}

QSlider* ParamPanel::slider(const std::string& name) const {
  for (std::size_t i = 0; i < schema_.size(); ++i)
    if (schema_[i].name == name) return rows_[i].slider;
  return nullptr;
}

QAbstractSpinBox* ParamPanel::spin_box(const std::string& name) const {
  for (std::size_t i = 0; i < schema_.size(); ++i)
    if (schema_[i].name == name) return rows_[i].spin;
  return nullptr;
}

Parameters drone_schema() {
  Parameters out;  // the core's declaration: the panel allows exactly what a test file allows
  for (const DroneProperty& p : salsa::drone_schema()) out.push_back(p.spec);
  return out;
}

}  // namespace salsa::gui
