#include "number_field.hpp"

#include <QKeyEvent>
#include <QLineEdit>
#include <algorithm>
#include <charconv>
#include <cmath>

#include "format.hpp"

namespace salsa::gui {

QObject* NumberField::refusals() {
  static NumberRefusals* all = new NumberRefusals;  // one for the program, never deleted (outlives every field)
  return all;
}

NumberField::NumberField(const Parameter& spec, QWidget* parent) : QAbstractSpinBox(parent), spec_(spec), value_(spec.min) {
  setKeyboardTracking(false);  // one change per edit (Enter, Tab, focus loss), not per keystroke
  setObjectName(QString::fromStdString(spec.name));
  if (spec_.description.empty()) setToolTip(QString::fromStdString("allowed: " + spec_.range()));
  show_value();
}

QString NumberField::text_of(double v) const {
  if (!special_.isEmpty() && v == spec_.min) return special_;
  return QString::fromStdString(format::number(v) + (spec_.unit.empty() ? "" : " " + spec_.unit));
}

QString NumberField::problem(const QString& typed, double* out) const {
  QString text = typed.trimmed();
  if (!special_.isEmpty() && text == special_) {
    if (out) *out = spec_.min;
    return {};
  }
  // The unit shown after the number may be kept, cut short or deleted.
  if (const QString unit = QString::fromStdString(spec_.unit); !unit.isEmpty() && text.endsWith(unit)) text.chop(unit.size());
  text = text.trimmed();
  if (text.startsWith('+')) text.remove(0, 1);
  const std::string s = text.toStdString();
  const std::string field = spec_.name + ": \"" + typed.trimmed().toStdString() + "\" ";
  double v = 0;
  const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), v);
  // A number as JSON writes it: no "inf", "nan", hex or leading dot (from_chars reads "inf" and "nan").
  const bool json_like = !s.empty() && s.find_first_of("iInNxXpP") == std::string::npos;
  if (error == std::errc::result_out_of_range && json_like)
    return QString::fromStdString(field + "is out of range (allowed: " + spec_.range() + ")");
  if (error != std::errc() || end != s.data() + s.size() || !json_like)
    return QString::fromStdString(field + "is not a number (allowed: " + spec_.range() + ")");
  // A whole number past 2^53 rounds as a double (2^53 + 1 reads 2^53): compared as written.
  long long n = 0;
  if (const auto r = std::from_chars(s.data(), s.data() + s.size(), n);
      spec_.is_integer() && r.ec == std::errc() && r.ptr == s.data() + s.size() && std::fabs(spec_.max) < 9e18 &&
      (n > static_cast<long long>(spec_.max) || n < static_cast<long long>(spec_.min)))
    return QString::fromStdString(field + "is out of range (allowed: " + spec_.range() + ")");
  if (const std::string why = spec_.check(v); !why.empty()) {
    const bool fraction = spec_.is_integer() && v >= spec_.min && v <= spec_.max;
    return QString::fromStdString(field + (fraction ? "is not a whole number (allowed: " + spec_.range() + ")" : why));
  }
  if (out) *out = v == 0 ? 0.0 : v;  // -0 is 0
  return {};
}

void NumberField::show_value() {
  const QString text = text_of(value_);
  if (lineEdit()->text() != text) lineEdit()->setText(text);
}

void NumberField::setValue(double v) {
  v = std::clamp(std::isfinite(v) ? v : spec_.min, spec_.min, spec_.max);
  const bool changed = v != value_;
  value_ = v;
  show_value();
  if (changed) Q_EMIT valueChanged(value_);
}

void NumberField::set_range(double min, double max) {
  spec_.min = min;
  spec_.max = max;
  setValue(value_);
}

void NumberField::set_special_text(const QString& text) {
  special_ = text;
  show_value();
}

bool NumberField::commit() {
  if (lineEdit()->text() == text_of(value_)) return true;
  double v = 0;
  if (QString why = problem(lineEdit()->text(), &v); !why.isEmpty()) {
    last_refusal_ = why;
    show_value();
    Q_EMIT refused(why);
    Q_EMIT static_cast<NumberRefusals*>(refusals())->refused(why);
    return false;
  }
  setValue(v);
  show_value();  // the value as written back ("1E3" reads 1000), also when it was unchanged
  return true;
}

void NumberField::stepBy(int steps) {
  if (!commit()) return;
  double step = spec_.step > 0 ? spec_.step : (spec_.max - spec_.min) / 100;
  if (adaptive_ && value_ != 0)  // a tenth of the value's decade
    step = std::max(step, std::pow(10.0, std::floor(std::log10(std::fabs(value_))) - 1));
  if (spec_.is_integer()) step = std::max(1.0, std::round(step));
  setValue(value_ + steps * step);
  lineEdit()->selectAll();
}

QAbstractSpinBox::StepEnabled NumberField::stepEnabled() const {
  if (isReadOnly()) return StepNone;
  StepEnabled e = StepNone;
  if (value_ < spec_.max) e |= StepUpEnabled;
  if (value_ > spec_.min) e |= StepDownEnabled;
  return e;
}

QValidator::State NumberField::validate(QString& input, int&) const {
  // Never Invalid: a key typed is never swallowed; commit() applies or refuses the whole text.
  return problem(input).isEmpty() ? QValidator::Acceptable : QValidator::Intermediate;
}

void NumberField::keyPressEvent(QKeyEvent* event) {
  if (event->key() == Qt::Key_Return || event->key() == Qt::Key_Enter) {
    commit();
    lineEdit()->selectAll();
    Q_EMIT editingFinished();
    event->accept();  // not on to the dialog's default button: the value is what Enter was for
    return;
  }
  QAbstractSpinBox::keyPressEvent(event);
}

void NumberField::focusOutEvent(QFocusEvent* event) {
  // Another field or button clicked, Tab: applied. The window deactivated (another window, or this one
  // closing): kept as typed, applied when the field is left.
  if (event->reason() != Qt::ActiveWindowFocusReason && window()->isVisible()) commit();
  QAbstractSpinBox::focusOutEvent(event);
}

QSize NumberField::sizeHint() const {
  const QSize base = QAbstractSpinBox::sizeHint();
  const QFontMetrics fm(font());
  int text = 0;
  for (double v : {spec_.min, spec_.max, value_}) text = std::max(text, fm.horizontalAdvance(text_of(v)));
  text = std::clamp(text, fm.horizontalAdvance("0000"), fm.horizontalAdvance("-0.000000 Wh"));
  return {std::max(base.width(), text + 40), base.height()};
}

QSize NumberField::minimumSizeHint() const { return sizeHint(); }

}  // namespace salsa::gui
