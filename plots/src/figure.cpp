#include "figure.hpp"

#include <QApplication>
#include <QTextLayout>
#include <QSaveFile>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "marks.hpp"  // the desktop's marks, drawn alike here
#include "salsa/plots/results.hpp"

namespace salsa::plots {

void ensure_application() {
  if (QCoreApplication::instance()) return;
  if (!std::getenv("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  if (!std::getenv("XDG_RUNTIME_DIR")) {  // Qt warns on stderr without one
    const std::string dir = "/tmp/salsa-runtime-" + std::to_string(::getuid());
    ::mkdir(dir.c_str(), 0700);
    qputenv("XDG_RUNTIME_DIR", dir.c_str());
  }
  static int argc = 1;
  static char name[] = "salsa";
  static char* argv[] = {name, nullptr};
  static QApplication app(argc, argv);
  // Qt's own diagnostics ("libpng error: Write Error" on a full disk) are raw library text; every
  // failure that matters reaches the caller as an exception naming the file instead.
  qInstallMessageHandler([](QtMsgType, const QMessageLogContext&, const QString&) {});
}

QColor palette(std::size_t i) {
  static const QColor colours[] = {0x4E79A7, 0xF28E2B, 0xE15759, 0x76B7B2, 0x59A14F,
                                   0xEDC948, 0xB07AA1, 0xFF9DA7, 0x9C755F, 0xBAB0AC};
  return colours[i % std::size(colours)];
}

QColor group_colour(std::size_t i) {
  static const QColor colours[] = {0xE69F00, 0x0072B2, 0x009E73, 0xD55E00, 0x56B4E9, 0xCC79A7, 0xF0E442};
  return colours[i % std::size(colours)];
}

QFont font(int pixels, bool bold) {
  QFont f("DejaVu Sans");
  f.setPixelSize(pixels);
  f.setBold(bold);
  return f;
}

QString tick_text(double value, double step) {
  int decimals = 0;
  while (decimals < 6 && std::abs(step * std::pow(10, decimals) - std::round(step * std::pow(10, decimals))) > 1e-6) ++decimals;
  if (std::abs(value) < step * 1e-9) value = 0;  // no "-0"
  return QString::number(value, 'f', decimals);
}

std::vector<double> nice_ticks(double lo, double hi, int max_ticks) {
  if (!(hi > lo)) lo -= 0.5, hi += 0.5;
  const double raw = (hi - lo) / std::max(1, max_ticks - 1);
  const double magnitude = std::pow(10, std::floor(std::log10(raw)));
  double step = 10 * magnitude;
  for (double m : {1.0, 2.0, 5.0})
    if (m * magnitude >= raw * (1 - 1e-9)) {
      step = m * magnitude;
      break;
    }
  const double first = std::floor(lo / step + 1e-9), last = std::ceil(hi / step - 1e-9);
  std::vector<double> ticks;
  for (double k = first; k <= last; ++k) ticks.push_back(k * step);
  return ticks;
}

Figure::Figure(const QString& title, int width, int height) : image_(width, height, QImage::Format_RGB32), title_(title) {
  ensure_application();
  image_.fill(Qt::white);
}

namespace {

/// Round ticks over [lo, hi] and the axis's ends: the outer ticks, or (exact) lo and hi with the
/// ticks inside them.
void axis(double lo, double hi, bool exact, std::vector<double>& ticks, double& step, double& from, double& to) {
  ticks = nice_ticks(lo, hi);
  step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1;
  if (!exact || !(hi > lo)) {
    from = ticks.front(), to = ticks.back();
    return;
  }
  const double slack = 1e-9 * step;
  std::erase_if(ticks, [&](double t) { return t < lo - slack || t > hi + slack; });
  from = lo, to = hi;
}

}  // namespace

void Figure::x_axis(const QString& label, double lo, double hi, bool exact) {
  x_label_ = label;
  axis(lo, hi, exact, x_ticks_, x_step_, x_lo_, x_hi_);
}

void Figure::y_axis(const QString& label, double lo, double hi, bool exact) {
  y_label_ = label;
  axis(lo, hi, exact, y_ticks_, y_step_, y_lo_, y_hi_);
}

void Figure::x_categories(const QString& label, const std::vector<QString>& names) {
  x_label_ = label;
  x_names_ = names;
  x_lo_ = -0.5, x_hi_ = static_cast<double>(names.size()) - 0.5;
}

void Figure::y_categories(const std::vector<QString>& names) {
  y_names_ = names;
  y_lo_ = static_cast<double>(names.size()) - 0.5, y_hi_ = -0.5;  // the first name at the top
}

QStringList wrapped(const QString& text, const QFont& f, double width, int max_lines, bool inside_words) {
  QStringList lines;
  QTextLayout layout(text, f);
  QTextOption option;
  option.setWrapMode(inside_words ? QTextOption::WrapAtWordBoundaryOrAnywhere : QTextOption::WordWrap);
  layout.setTextOption(option);
  layout.beginLayout();
  for (QTextLine line = layout.createLine(); line.isValid(); line = layout.createLine()) {
    line.setLineWidth(std::max(width, 1.0));
    lines << text.mid(line.textStart(), line.textLength()).trimmed();
  }
  layout.endLayout();
  if (lines.isEmpty()) lines << QString();
  if (lines.size() > max_lines) {
    const QString rest = lines.mid(max_lines - 1).join(' ');
    lines = lines.mid(0, max_lines - 1);
    lines << QFontMetricsF(f).elidedText(rest, Qt::ElideRight, width);
  }
  return lines;
}

namespace {

LayoutObserver& layout_observer() {
  static LayoutObserver observer;
  return observer;
}

constexpr double line_step = 18;  // between two lines of 15-pixel text

/// Whether `text` needs more than `width` pixels in `m` (the measure the layout reserves room by).
bool wider(const QFontMetrics& m, const QString& text, double width) { return m.horizontalAdvance(text) > width; }

}  // namespace

void observe_layouts(LayoutObserver observer) { layout_observer() = std::move(observer); }

QPainter& Figure::begin() {
  const QFont text_font = font(15), label_font = font(18), title_font = font(24, true);
  const QFontMetrics tick_metrics(text_font), label_metrics(label_font), title_metrics(title_font);
  const double width = image_.width();

  // ---- Layout: title on top, axis labels and tick labels outside the plot, legend on the right. Text
  // wider than its place wraps, and the canvas grows taller for it (never narrower), so that no label
  // pushes the plot area off the canvas.
  const QStringList title_lines = wider(title_metrics, title_, width - 40) ? wrapped(title_, title_font, width - 40, 3) : QStringList{title_};
  const double top = 70 + 29 * static_cast<double>(title_lines.size() - 1);

  // Names on the left: at most 45 % of the width, wrapped beyond.
  double left = 95;
  for (const QString& name : y_names_) left = std::max(left, 30.0 + std::min(0.45 * width, 1.0 * tick_metrics.horizontalAdvance(name)));
  std::vector<QStringList> y_lines;
  int y_most_lines = 1;
  for (const QString& name : y_names_) {
    y_lines.push_back(wider(tick_metrics, name, left - 30) ? wrapped(name, text_font, left - 20) : QStringList{name});
    y_most_lines = std::max(y_most_lines, static_cast<int>(y_lines.back().size()));
  }
  // Numbers on the left, the axis label beside them, apart.
  double tick_width = 0;
  for (double t : y_ticks_) tick_width = std::max(tick_width, 1.0 * tick_metrics.horizontalAdvance(tick_text(t, y_step_)));
  // The axis label's centre is 72 px left of the axis, or further when the numbers reach it (its 22 px
  // tall line clear of them; see the drawing below), the axis moving right to make room.
  if (tick_width > 47) left = std::max(left, tick_width + 55);

  // The legend: at most 30 % of the width, each entry wrapped beyond.
  double legend_width = 0, inner = 0, slot = 0;
  auto lay_out_legend = [&] {
    legend_width = 0;
    for (const auto& e : legend_) legend_width = std::max(legend_width, 50.0 + tick_metrics.horizontalAdvance(e.text));
    legend_width = std::min(legend_width, 0.3 * width);
    legend_x_ = width - 30 - extra_right_ - legend_width;
    inner = width - left - (30 + (legend_width > 0 ? legend_width + 10 : 0) + extra_right_);  // the plot area's width
    slot = x_names_.empty() ? inner : inner / static_cast<double>(x_names_.size());
  };
  lay_out_legend();
  // Names below: each within its category's width, on at most 3 lines broken between words; else
  // numbered, and the legend says which number is which.
  const bool keyed = std::any_of(x_names_.begin(), x_names_.end(), [&](const QString& name) {
    if (!wider(tick_metrics, name, std::min(300.0, slot - 8))) return false;
    const QStringList lines = wrapped(name, text_font, slot - 8, 4, false);
    return lines.size() > 3 || std::any_of(lines.begin(), lines.end(), [&](const QString& l) { return wider(tick_metrics, l, slot - 7); });
  });
  if (keyed) {
    for (std::size_t i = 0; i < x_names_.size(); ++i) {
      legend_.push_back({LegendEntry::note, Qt::black, QString::number(i + 1) + ": " + x_names_[i]});
      x_names_[i] = QString::number(i + 1);
    }
    lay_out_legend();
  }
  legend_lines_.clear();
  double legend_height = 0;
  for (const auto& e : legend_) {
    legend_lines_.push_back(wider(tick_metrics, e.text, legend_width - 50) ? wrapped(e.text, text_font, legend_width - 42) : QStringList{e.text});
    legend_height += 28 + line_step * static_cast<double>(legend_lines_.back().size() - 1);
  }
  std::vector<QStringList> x_lines;
  int x_most_lines = 1;
  for (const QString& name : x_names_) {
    x_lines.push_back(wider(tick_metrics, name, std::min(300.0, slot - 8)) ? wrapped(name, text_font, std::max(40.0, slot - 8)) : QStringList{name});
    x_most_lines = std::max(x_most_lines, static_cast<int>(x_lines.back().size()));
  }
  // The axis label below them, centred on the plot and as wide as the canvas allows there.
  const double x_centre = left + inner / 2, x_room = 2 * (std::min(x_centre, width - x_centre) - 10);
  const QStringList x_label_lines = wider(label_metrics, x_label_, inner) ? wrapped(x_label_, label_font, x_room, 3) : QStringList{x_label_};
  const double below = line_step * (x_most_lines - 1), bottom = 85 + below + 22 * static_cast<double>(x_label_lines.size() - 1);

  // The canvas's height: the plot's rows hold their wrapped names; the legend fits beside the plot.
  double height = image_.height();
  if (y_most_lines > 1) height = std::max(height, top + bottom + static_cast<double>(y_names_.size()) * (line_step * y_most_lines + 8));
  height = std::max(height, top + 4 + legend_height + 10);
  if (height > image_.height()) {
    image_ = QImage(image_.width(), static_cast<int>(std::ceil(height)), QImage::Format_RGB32);
    image_.fill(Qt::white);
  }
  plot_ = QRectF(left, top, inner, image_.height() - top - bottom);
  if (equal_) {  // one metre is as many pixels across as up; centre the smaller side
    const double scale = std::min(plot_.width() / (x_hi_ - x_lo_), plot_.height() / (y_hi_ - y_lo_));
    const double w = scale * (x_hi_ - x_lo_), h = scale * (y_hi_ - y_lo_);
    plot_ = QRectF(plot_.left() + (plot_.width() - w) / 2, plot_.top() + (plot_.height() - h) / 2, w, h);
  }
  if (layout_observer()) layout_observer()(title_, image_.size(), plot_);

  // ---- Title, grid, ticks, labels.
  painter_.begin(&image_);
  painter_.setRenderHint(QPainter::Antialiasing);
  QPainter& p = painter_;
  p.setPen(Qt::black);
  p.setFont(title_font);
  if (title_lines.size() == 1) p.drawText(QRectF(0, 12, width, 40), Qt::AlignCenter, title_);
  else p.drawText(QRectF(20, 12, width - 40, 40 + 29 * static_cast<double>(title_lines.size() - 1)), Qt::AlignCenter, title_lines.join('\n'));
  p.setFont(text_font);
  const QPen grid(QColor(225, 225, 225), 1);
  for (std::size_t i = 0; i < y_names_.size(); ++i) {
    const double y = at(x_lo_, static_cast<double>(i)).y();
    if (i % 2 == 0) p.fillRect(QRectF(plot_.left(), y - (plot_.height() / static_cast<double>(y_names_.size())) / 2, plot_.width(), plot_.height() / static_cast<double>(y_names_.size())), QColor(246, 246, 246));
    const double h = std::max(22.0, line_step * static_cast<double>(y_lines[i].size()) + 4);
    p.drawText(QRectF(10, y - h / 2, plot_.left() - 20, h), Qt::AlignRight | Qt::AlignVCenter, y_lines[i].join('\n'));
  }
  for (std::size_t i = 0; i < x_ticks_.size(); ++i) {
    const double x = at(x_ticks_[i], y_lo_).x();
    p.setPen(grid);
    p.drawLine(QPointF(x, plot_.top()), QPointF(x, plot_.bottom()));
    p.setPen(Qt::black);
    p.drawLine(QPointF(x, plot_.bottom()), QPointF(x, plot_.bottom() + 6));
    p.drawText(QRectF(x - 60, plot_.bottom() + 8, 120, 22), Qt::AlignHCenter | Qt::AlignTop, tick_text(x_ticks_[i], x_step_));
  }
  for (std::size_t i = 0; i < x_names_.size(); ++i) {
    const double x = at(static_cast<double>(i), y_lo_).x();
    const double w = x_lines[i].size() == 1 && !wider(tick_metrics, x_names_[i], 300) ? 300 : std::max(300.0, slot);
    p.drawText(QRectF(x - w / 2, plot_.bottom() + 8, w, 22 + line_step * static_cast<double>(x_lines[i].size() - 1)), Qt::AlignHCenter | Qt::AlignTop,
               x_lines[i].join('\n'));
  }
  for (std::size_t i = 0; i < y_ticks_.size(); ++i) {
    const double y = at(x_lo_, y_ticks_[i]).y();
    p.setPen(grid);
    p.drawLine(QPointF(plot_.left(), y), QPointF(plot_.right(), y));
    p.setPen(Qt::black);
    p.drawLine(QPointF(plot_.left() - 6, y), QPointF(plot_.left(), y));
    p.drawText(QRectF(plot_.left() - 10 - std::max(90.0, tick_width), y - 11, std::max(90.0, tick_width), 22), Qt::AlignRight | Qt::AlignVCenter,
               tick_text(y_ticks_[i], y_step_));
  }
  p.setFont(label_font);
  if (x_label_lines.size() == 1 && !wider(label_metrics, x_label_, plot_.width()))
    p.drawText(QRectF(plot_.left(), plot_.bottom() + 36 + below, plot_.width(), 30), Qt::AlignCenter, x_label_);
  else
    p.drawText(QRectF(x_centre - x_room / 2, plot_.bottom() + 36 + below, x_room, 30 + 22 * static_cast<double>(x_label_lines.size() - 1)),
               Qt::AlignHCenter | Qt::AlignTop, x_label_lines.join('\n'));
  p.save();
  p.translate(std::max(22.0, std::min(plot_.left() - 72, plot_.left() - tick_width - 25)), plot_.center().y());
  p.rotate(-90);
  p.drawText(QRectF(-plot_.height() / 2 - 100, -12, plot_.height() + 200, 30), Qt::AlignCenter, y_label_);
  p.restore();
  p.setClipRect(plot_);
  return p;
}

QPointF Figure::at(double x, double y) const {
  return {plot_.left() + (x - x_lo_) / (x_hi_ - x_lo_) * plot_.width(),
          plot_.bottom() - (y - y_lo_) / (y_hi_ - y_lo_) * plot_.height()};
}

void Figure::save(const std::filesystem::path& file) {
  QPainter& p = painter_;
  p.setClipping(false);
  p.setBrush(Qt::NoBrush);
  p.setPen(QPen(Qt::black, 1));
  p.drawRect(plot_);
  // ---- Legend: one row per entry, a symbol then the text.
  p.setFont(font(15));
  double y = plot_.top() + 4;
  const double x = legend_x_;
  for (std::size_t i = 0; i < legend_.size(); ++i) {
    const LegendEntry& e = legend_[i];
    const QRectF symbol(x, y + 4, 34, 16);
    p.setPen(Qt::NoPen);
    p.setBrush(Qt::NoBrush);
    switch (e.kind) {
      case LegendEntry::line: p.setPen(QPen(e.colour, 3, e.style)); p.drawLine(QPointF(symbol.left(), symbol.center().y()), QPointF(symbol.right(), symbol.center().y())); break;
      case LegendEntry::band: p.fillRect(symbol, e.colour); break;
      case LegendEntry::dot: p.setBrush(e.colour); p.drawEllipse(symbol.center(), 6, 6); break;
      case LegendEntry::ring: p.setPen(QPen(e.colour, 2)); p.drawEllipse(symbol.center(), 6, 6); break;
      case LegendEntry::box: p.setPen(QPen(e.colour.darker(160), 1.5)); p.setBrush(e.colour); p.drawRect(symbol.adjusted(6, 0, -6, 0)); break;
      case LegendEntry::square: p.setPen(QPen(e.colour.darker(140), 1)); p.setBrush(e.colour); p.drawRect(symbol.adjusted(9, 0, -9, 0)); break;
      case LegendEntry::cross: gui::draw_cross(p, symbol.center(), e.colour); break;
      case LegendEntry::note: break;
    }
    p.setPen(Qt::black);
    for (const QString& line : legend_lines_[i]) {
      p.drawText(QRectF(x + 42, y, 1000, 24), Qt::AlignLeft | Qt::AlignVCenter, line);
      y += line_step;
    }
    y += 28 - line_step;
  }
  p.end();
  write_png(image_, file);
}

void write_png(const QImage& image, const std::filesystem::path& file) {
  QSaveFile out(QString::fromStdString(file.string()));
  if (!out.open(QIODevice::WriteOnly) || !image.save(&out, "PNG") || !out.commit())
    throw std::runtime_error(file.string() + ": cannot write PNG (" + out.errorString().toStdString() + ")");
}

}  // namespace salsa::plots
