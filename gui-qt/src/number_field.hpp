#pragma once
// The one number input of the desktop. It takes what a test file takes: any JSON number ("1e308",
// "-0.5", "2E-3"), exactly, over the declared range; the text typed is never changed while typing
// (no key is swallowed) and never silently on commit: on Enter or focus loss a text that is no number,
// out of range or not whole (where whole numbers are asked) is refused in one line naming the field
// and the allowed range, and the field shows its last value again. Arrow keys and the wheel step it.
#include <QAbstractSpinBox>
#include <QString>
#include <cstdint>

#include "salsa/parameters.hpp"

namespace salsa::gui {

class NumberField : public QAbstractSpinBox {
  Q_OBJECT
 public:
  /// `spec`: its name (for messages), range, unit (shown after the number) and step (1: whole numbers).
  explicit NumberField(const Parameter& spec, QWidget* parent = nullptr);
  double value() const { return value_; }
  /// The value as a whole number (for whole-number fields).
  std::int64_t whole() const { return static_cast<std::int64_t>(value_); }
  /// Shows `v` (kept in range); emits valueChanged() when it differs.
  void setValue(double v);
  const Parameter& spec() const { return spec_; }
  /// A new range (the value kept in it).
  void set_range(double min, double max);
  /// Arrow keys step by a tenth of the value's decade (for ranges over decades).
  void set_adaptive(bool on) { adaptive_ = on; }
  /// Shown instead of the minimum ("never", "none"); typing it back means the minimum.
  void set_special_text(const QString& text);
  /// The text shown for `v`.
  QString text_of(double v) const;
  /// Empty when `text` is a number this field takes (written to *out), else the one-line refusal.
  QString problem(const QString& text, double* out = nullptr) const;
  /// The last refusal (tests).
  const QString& last_refusal() const { return last_refusal_; }

  void stepBy(int steps) override;
  QValidator::State validate(QString& input, int& pos) const override;
  QSize sizeHint() const override;
  QSize minimumSizeHint() const override;

  /// Every field's refusals, for the window's status line (one object for the program).
  static QObject* refusals();

 Q_SIGNALS:
  void valueChanged(double value);
  /// A typed text was refused: the one-line reason.
  void refused(const QString& why);

 protected:
  StepEnabled stepEnabled() const override;
  void keyPressEvent(QKeyEvent* event) override;
  void focusOutEvent(QFocusEvent* event) override;

 private:
  /// Applies the typed text or refuses it; false when refused.
  bool commit();
  void show_value();
  Parameter spec_;
  double value_ = 0;
  QString special_;
  bool adaptive_ = false;
  QString last_refusal_;
};

/// The object behind NumberField::refusals(): one signal for every field's refusal.
class NumberRefusals : public QObject {
  Q_OBJECT
 Q_SIGNALS:
  void refused(const QString& why);
};

}  // namespace salsa::gui
