#pragma once
// Sliders built from a declared parameter schema: per parameter a slider and a spin box (whole-number
// parameters get an integer spin box), range, step and unit from the declaration, the meaning as tooltip.
#include <QWidget>
#include <vector>

#include "salsa/parameters.hpp"

class QSlider;
class QAbstractSpinBox;
class QFormLayout;

namespace salsa::gui {

class ParamPanel : public QWidget {
  Q_OBJECT
 public:
  explicit ParamPanel(QWidget* parent = nullptr);
  /// Rebuilds the rows for `schema`, showing `values` (defaults where missing). Emits nothing.
  void set_schema(const Parameters& schema, const ParameterValues& values = {});
  /// Shows `value` for `name` without emitting changed().
  void set_value(const std::string& name, double value);
  double value(const std::string& name) const;
  const Parameters& schema() const { return schema_; }
  QSlider* slider(const std::string& name) const;
  QAbstractSpinBox* spin_box(const std::string& name) const;

 Q_SIGNALS:
  /// The user changed a value (slider released or moved, spin box edited): once per change.
  void changed(const std::string& name, double value);

 private:
  struct Row {
    QSlider* slider = nullptr;
    QAbstractSpinBox* spin = nullptr;
  };
  int to_slider(const Parameter& p, double v) const;
  double from_slider(const Parameter& p, int s) const;
  void show_value(std::size_t i, double v);
  Parameters schema_;
  std::vector<Row> rows_;
  QFormLayout* form_;
  bool updating_ = false;
};

/// The drone properties as the panel edits them: the core's salsa::drone_schema() (the ranges a test
/// file allows; check_drone still has the last word on the combination with dt).
Parameters drone_schema();

}  // namespace salsa::gui
