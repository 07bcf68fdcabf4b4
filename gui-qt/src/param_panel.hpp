#pragma once
// Sliders built from a declared parameter schema: per parameter a slider and a number field
// (NumberField: any JSON number over the declared range, refused in one line otherwise), range, step and
// unit from the declaration, the meaning as tooltip. A range that spans two decades or more gets a
// logarithmic slider (equal travel, equal ratio), so a drag of a few pixels never jumps from 60 m to
// 1000 m; a range across zero is logarithmic on each side (fine near 0: a breeze of 3 m/s is set in
// steps of 0.1 m/s). Every slider has at most 1000 positions, one arrow key each (finer than a pixel).
// Fields apply a typed value on Enter or focus loss, once.
#include <QWidget>
#include <vector>

#include "salsa/core/model/drone_config.hpp"
#include "salsa/parameters.hpp"

class QSlider;
class QFormLayout;

namespace salsa::gui {

class NumberField;

class ParamPanel : public QWidget {
  Q_OBJECT
 public:
  explicit ParamPanel(QWidget* parent = nullptr);
  /// Shows `schema`'s rows with `values` (defaults where missing). Emits nothing. The same schema as now
  /// updates the rows in place; another replaces them, the old widgets deleted once control returns to
  /// the event loop (this may be called from a row's own signal, mid key press).
  void set_schema(const Parameters& schema, const ParameterValues& values = {});
  /// Shows `value` for `name` without emitting changed().
  void set_value(const std::string& name, double value);
  double value(const std::string& name) const;
  const Parameters& schema() const { return schema_; }
  QSlider* slider(const std::string& name) const;
  /// The value a slider position stands for (tests).
  double slider_value(const std::string& name, int position) const;
  NumberField* spin_box(const std::string& name) const;

 Q_SIGNALS:
  /// The user changed a value (slider released or moved, spin box edited): once per change.
  void changed(const std::string& name, double value);

 private:
  struct Row {
    QSlider* slider = nullptr;
    NumberField* spin = nullptr;
  };
  /// The slider's mapping: positions 0..positions(p), linear or logarithmic.
  static int positions(const Parameter& p);
  static bool logarithmic(const Parameter& p);
  static int decimals(const Parameter& p);
  static int to_slider(const Parameter& p, double v);
  static double from_slider(const Parameter& p, int s);
  void show_value(std::size_t i, double v);
  void build_rows();
  Parameters schema_;
  std::vector<Row> rows_;
  QFormLayout* form_;
  bool updating_ = false;
};

/// A wheel turned over `w` (a spin box, slider or combo box) scrolls the panel it sits in unless `w` has
/// the keyboard focus (clicked or tabbed into): scrolling a long panel must not edit the values it
/// passes over. ParamPanel's rows have this; call it for other inputs of a scrolled panel.
void wheel_scrolls_unless_focused(QWidget* w);

/// The drone properties of one section (the body, the battery and power model, sensor noise) as the
/// panels edit them: the core's salsa::drone_schema() (the ranges a test file allows; check_drone still
/// has the last word on the combination with dt).
Parameters drone_schema(DroneSection section);

}  // namespace salsa::gui
