#include "param_panel.hpp"

#include <QAbstractScrollArea>
#include <QApplication>
#include <QWheelEvent>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QSlider>
#include <algorithm>
#include <cmath>

#include "number_field.hpp"
#include "salsa/core/model/drone_config.hpp"

namespace salsa::gui {
namespace {
double step_of(const Parameter& p) { return p.step > 0 ? p.step : (p.max - p.min) / 100; }
int decimals_of(const Parameter& p) {
  const double s = step_of(p);
  return p.is_integer() || s >= 1 ? 0 : std::clamp(static_cast<int>(std::ceil(-std::log10(s))), 1, 6);
}
constexpr int log_positions = 1000;
/// The logarithmic mapping works on v + shift, which is > 0 over the range: a range from 0 starts
/// one step above it, so [0, 1000] m in steps of 0.5 m maps [0.5, 1000.5].
double shift_of(const Parameter& p) { return p.min > 0 ? 0 : step_of(p) - p.min; }
/// A range across zero ([-1000, 1000] m/s of wind) is logarithmic on each side of it: u = ±ln(1 + |v| / step),
/// so a slider's travel is as fine near 0 as the step and coarse only far out.
bool signed_range(const Parameter& p) { return p.min < 0 && p.max > 0; }
double signed_u(const Parameter& p, double v) { return std::copysign(std::log1p(std::fabs(v) / step_of(p)), v); }
double signed_v(const Parameter& p, double u) { return std::copysign(step_of(p) * std::expm1(std::fabs(u)), u); }
int clamp_int(double v) { return static_cast<int>(std::clamp(v, -2147483647.0, 2147483647.0)); }

/// Hands a wheel event over an unfocused input to the scroll area around it.
class WheelGuard : public QObject {
 public:
  bool eventFilter(QObject* watched, QEvent* event) override {
    auto* w = qobject_cast<QWidget*>(watched);
    if (event->type() != QEvent::Wheel || !w || w->hasFocus()) return false;
    for (QWidget* up = w->parentWidget(); up; up = up->parentWidget())
      if (auto* area = qobject_cast<QAbstractScrollArea*>(up)) {
        QApplication::sendEvent(area->viewport(), event);
        return true;
      }
    event->ignore();
    return true;
  }
};
}  // namespace

void wheel_scrolls_unless_focused(QWidget* w) {
  static WheelGuard* guard = new WheelGuard;  // one for the whole program, never deleted (outlives every widget)
  w->setFocusPolicy(Qt::StrongFocus);         // not WheelFocus: a wheel passing over takes no focus
  w->installEventFilter(guard);
}

int ParamPanel::decimals(const Parameter& p) {
  // A logarithmic range is fine near its low end: two decimals at least, where its step allows.
  return p.is_integer() ? 0 : logarithmic(p) && p.step <= 0 ? std::max(decimals_of(p), 2) : decimals_of(p);
}

ParamPanel::ParamPanel(QWidget* parent) : QWidget(parent), form_(new QFormLayout(this)) {
  form_->setContentsMargins(0, 0, 0, 0);
  form_->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
}

bool ParamPanel::logarithmic(const Parameter& p) {
  if (signed_range(p)) return std::isfinite(p.max - p.min) && step_of(p) > 0 && std::max(-p.min, p.max) / step_of(p) >= 100;
  const double shift = shift_of(p);
  return std::isfinite(p.max - p.min) && step_of(p) > 0 && (p.max + shift) / (p.min + shift) >= 100;
}

int ParamPanel::positions(const Parameter& p) {
  if (logarithmic(p)) return log_positions;
  const double steps = std::ceil((p.max - p.min) / step_of(p) - 1e-9);
  return std::isfinite(steps) ? clamp_int(std::clamp(steps, 1.0, static_cast<double>(log_positions))) : log_positions;
}

int ParamPanel::to_slider(const Parameter& p, double v) {
  const int n = positions(p);
  double f = (v - p.min) / (p.max - p.min);
  if (logarithmic(p) && signed_range(p)) {
    f = (signed_u(p, v) - signed_u(p, p.min)) / (signed_u(p, p.max) - signed_u(p, p.min));
  } else if (logarithmic(p)) {
    const double shift = shift_of(p);
    f = std::log((std::max(v, p.min) + shift) / (p.min + shift)) / std::log((p.max + shift) / (p.min + shift));
  }
  if (!std::isfinite(f)) f = 0;
  return static_cast<int>(std::lround(std::clamp(f, 0.0, 1.0) * n));
}

double ParamPanel::from_slider(const Parameter& p, int s) {
  const int n = positions(p);
  const double f = std::clamp(static_cast<double>(s) / n, 0.0, 1.0);
  double v = p.min + f * (p.max - p.min);
  if (logarithmic(p) && signed_range(p)) {
    v = signed_v(p, signed_u(p, p.min) + f * (signed_u(p, p.max) - signed_u(p, p.min)));
  } else if (logarithmic(p)) {
    const double shift = shift_of(p);
    v = (p.min + shift) * std::pow((p.max + shift) / (p.min + shift), f) - shift;
  }
  // On the declared step's grid (whole numbers stay whole), else at the spin box's decimals (what it
  // shows is what runs); the ends exactly.
  // Across zero, the grid is counted from 0 (divided by a whole 1 / step: 3 m/s, not 3.0000000000000004).
  if (p.step > 0 && signed_range(p) && 1 / p.step == std::round(1 / p.step)) v = std::round(v / p.step) / std::round(1 / p.step);
  else if (p.step > 0) v = p.min + std::round((v - p.min) / p.step) * p.step;
  else v = std::round(v * std::pow(10.0, decimals(p))) / std::pow(10.0, decimals(p));
  if (s <= 0) v = p.min;
  if (s >= n) v = p.max;
  return std::clamp(v, p.min, p.max);
}

double ParamPanel::slider_value(const std::string& name, int position) const {
  for (const Parameter& p : schema_)
    if (p.name == name) return from_slider(p, position);
  return std::nan("");
}

void ParamPanel::set_schema(const Parameters& schema, const ParameterValues& values) {
  const auto same_rows = [&] {
    if (schema.size() != schema_.size() || rows_.size() != schema_.size()) return false;
    for (std::size_t i = 0; i < schema.size(); ++i) {
      const Parameter &a = schema[i], &b = schema_[i];
      if (a.name != b.name || a.min != b.min || a.max != b.max || a.step != b.step || a.unit != b.unit) return false;
    }
    return true;
  };
  const bool in_place = same_rows();
  schema_ = schema;
  if (!in_place) build_rows();
  for (std::size_t i = 0; i < schema_.size(); ++i) {
    const Parameter& p = schema_[i];
    show_value(i, values.has(p.name) ? values.get(p.name) : p.value);
  }
}

void ParamPanel::build_rows() {
  // The old rows go once the event loop is back: one of them may be the widget whose signal led here.
  while (form_->rowCount() > 0) {
    const QFormLayout::TakeRowResult row = form_->takeRow(0);
    for (QLayoutItem* item : {row.labelItem, row.fieldItem}) {
      if (!item) continue;
      if (QWidget* w = item->widget()) {
        w->hide();
        w->setParent(nullptr);
        w->disconnect(this);
        for (QObject* child : w->findChildren<QObject*>()) child->disconnect(this);
        w->deleteLater();
      }
      delete item;
    }
  }
  rows_.clear();
  for (std::size_t i = 0; i < schema_.size(); ++i) {
    const Parameter& p = schema_[i];
    auto* field = new QWidget;
    auto* line = new QHBoxLayout(field);
    line->setContentsMargins(0, 0, 0, 0);
    Row row;
    row.slider = new QSlider(Qt::Horizontal);
    row.slider->setRange(0, positions(p));
    row.slider->setSingleStep(1);
    row.slider->setPageStep(std::max(1, positions(p) / 20));
    row.slider->setObjectName(QString::fromStdString(p.name) + "_slider");
    row.spin = new NumberField(p);
    if (logarithmic(p)) row.spin->set_adaptive(true);
    connect(row.spin, &NumberField::valueChanged, this, [this, i](double v) {
      if (updating_) return;
      show_value(i, v);
      Q_EMIT changed(schema_[i].name, v);
    });
    row.spin->setObjectName(QString::fromStdString(p.name));
    row.spin->setMinimumWidth(90);
    connect(row.slider, &QSlider::valueChanged, this, [this, i](int s) {
      if (updating_) return;
      const double v = from_slider(schema_[i], s);
      const bool same = v == rows_[i].spin->value();
      show_value(i, v);
      // The slider stays where it was moved: snapped back to the value's own position, a position that
      // rounds onto the same step would hold it there and the next arrow key would do nothing again.
      const bool was = updating_;
      updating_ = true;
      rows_[i].slider->setValue(s);
      updating_ = was;
      if (!same) Q_EMIT changed(schema_[i].name, v);
    });
    const QString tip = QString::fromStdString(p.description + " (allowed: " + p.range() + ")") +
                        (logarithmic(p) ? "; the slider is logarithmic, arrow keys move it finely" : "");
    row.slider->setToolTip(tip);
    row.spin->setToolTip(tip);
    wheel_scrolls_unless_focused(row.slider);
    wheel_scrolls_unless_focused(row.spin);
    line->addWidget(row.slider, 1);
    line->addWidget(row.spin);
    auto* label = new QLabel(QString::fromStdString(p.name).replace('_', ' '));
    label->setToolTip(tip);
    form_->addRow(label, field);
    rows_.push_back(row);
  }
  // New rows join the window's tab order at its end: put them back where the panel is, after the input
  // before it (Tab from the map box goes on to the map's parameters).
  QWidget* before = previousInFocusChain();
  while (before && before != this && (before->focusPolicy() == Qt::NoFocus || isAncestorOf(before)))
    before = before->previousInFocusChain();
  if (!before || before == this || before == window()) return;
  for (const Row& row : rows_)
    for (QWidget* w : {static_cast<QWidget*>(row.slider), static_cast<QWidget*>(row.spin)}) {
      QWidget::setTabOrder(before, w);
      before = w;
    }
}

void ParamPanel::show_value(std::size_t i, double v) {
  const bool was = updating_;
  updating_ = true;
  const Parameter& p = schema_[i];
  rows_[i].slider->setValue(to_slider(p, v));
  rows_[i].spin->setValue(v);
  updating_ = was;
}

void ParamPanel::set_value(const std::string& name, double value) {
  for (std::size_t i = 0; i < schema_.size(); ++i)
    if (schema_[i].name == name) show_value(i, value);
}

double ParamPanel::value(const std::string& name) const {
  for (std::size_t i = 0; i < schema_.size(); ++i)
    if (schema_[i].name == name) return rows_[i].spin->value();
  return std::nan("");
}

QSlider* ParamPanel::slider(const std::string& name) const {
  for (std::size_t i = 0; i < schema_.size(); ++i)
    if (schema_[i].name == name) return rows_[i].slider;
  return nullptr;
}

NumberField* ParamPanel::spin_box(const std::string& name) const {
  for (std::size_t i = 0; i < schema_.size(); ++i)
    if (schema_[i].name == name) return rows_[i].spin;
  return nullptr;
}

Parameters drone_schema(DroneSection section) {
  Parameters out;  // the core's declaration: the panel allows exactly what a test file allows
  for (const DroneProperty& p : salsa::drone_schema())
    if (p.section == section || (section == DroneSection::energy && p.section == DroneSection::returning)) out.push_back(p.spec);  // return to base: with the battery
  return out;
}

}  // namespace salsa::gui
