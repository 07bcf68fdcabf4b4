#pragma once
// A plot frame drawn with QPainter: title, axes with round ticks and grid, axis labels, a legend in a
// column on the right. The data is drawn between begin() and save() in data coordinates through at().
#include <QColor>
#include <QFont>
#include <QImage>
#include <QPainter>
#include <QString>

#include <QStringList>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace salsa::plots {

/// Makes the offscreen QApplication a headless program needs for charts and fonts.
void ensure_application();

/// Colours of series, by index (Tableau 10: distinguishable, and in grey scale too).
QColor palette(std::size_t i);
/// Colours of drone groups, in group order: Okabe & Ito's colour-blind-safe set (black left for
/// totals, yellow last: faint on white).
QColor group_colour(std::size_t i);
QFont font(int pixels, bool bold = false);
/// A tick value as text with as many decimals as the step needs.
QString tick_text(double value, double step);

/// `text` broken into lines at most `width` pixels wide in `f`: at spaces where it can, inside a word
/// where a word alone is wider (unless `inside_words` is false: such a line is then wider); past
/// `max_lines` the last line ends in "…".
QStringList wrapped(const QString& text, const QFont& f, double width, int max_lines = 6, bool inside_words = true);

struct LegendEntry {
  enum Kind { line, band, dot, ring, box, square, cross, note } kind;  // note: text only
  QColor colour;
  QString text;
  Qt::PenStyle style = Qt::SolidLine;  // of a line
};

/// Writes `image` as a PNG whole or not at all (QSaveFile: a temporary file renamed over `file`), so a
/// run killed while drawing never leaves a truncated plot; runtime_error naming the file.
void write_png(const QImage& image, const std::filesystem::path& file);

/// Called by each Figure once laid out, with its canvas and plot area: lets tests measure the layout
/// that is drawn. Set it before drawing and from one thread only.
using LayoutObserver = std::function<void(const QString& title, QSize canvas, QRectF plot)>;
void observe_layouts(LayoutObserver observer);

/// The layout adapts to its text: a label wider than its place is wrapped (at most 6 lines); the legend
/// takes at most 30 % of the width, names on the left 45 %; category names below that do not fit in 3
/// lines broken between words are numbered, with the key in the legend; the canvas grows taller (never
/// narrower than asked) until every legend entry, name and axis label has its room, so the plot area
/// stays on the canvas.
class Figure {
 public:
  /// A canvas of `width` × `height` pixels, or taller when the labels need it (see begin()).
  explicit Figure(const QString& title, int width, int height);

  /// A numeric axis over round ticks covering [lo, hi]; `exact`: the axis is [lo, hi] itself, with
  /// the round ticks inside it (a map's bounds as the frame, not the next round numbers).
  void x_axis(const QString& label, double lo, double hi, bool exact = false);
  void y_axis(const QString& label, double lo, double hi, bool exact = false);
  /// Named positions 0 … n-1 (x: below the axis; y: top to bottom, names on the left).
  void x_categories(const QString& label, const std::vector<QString>& names);
  void y_categories(const std::vector<QString>& names);
  void legend(std::vector<LegendEntry> entries) { legend_ = std::move(entries); }
  void equal_aspect() { equal_ = true; }
  void reserve_right(int pixels) { extra_right_ = pixels; }

  /// Lays the frame out and draws the background, grid and axes; data drawn next is clipped to the
  /// plot area.
  QPainter& begin();
  QPointF at(double x, double y) const;
  double pixels_per_x() const { return plot_.width() / (x_hi_ - x_lo_); }
  QRectF plot_area() const { return plot_; }
  QSize canvas() const { return image_.size(); }
  QPainter& painter() { return painter_; }
  /// Draws the border and legend and writes the PNG. Throws std::runtime_error naming the file.
  void save(const std::filesystem::path& file);

 private:
  QImage image_;
  QPainter painter_;
  QString title_, x_label_, y_label_;
  std::vector<double> x_ticks_, y_ticks_;
  double x_step_ = 1, y_step_ = 1;  // between round ticks
  std::vector<QString> x_names_, y_names_;
  double x_lo_ = 0, x_hi_ = 1, y_lo_ = 0, y_hi_ = 1;
  bool equal_ = false;
  int extra_right_ = 0;
  std::vector<LegendEntry> legend_;
  QRectF plot_;
  double legend_x_ = 0;
  std::vector<QStringList> legend_lines_;  // each entry's text, wrapped
};

}  // namespace salsa::plots
