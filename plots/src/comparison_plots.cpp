// The queue's comparison plots: comparison.png and did.png, paired differences A − B with their 95 % intervals.
#include "salsa/plots/results.hpp"

#include <QFile>

#include <algorithm>
#include <optional>

#include "salsa/core/files/csv_reader.hpp"
#include "comparison_plots.hpp"
#include "figure.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;

namespace {

// One row of an interval plot: a label on the left, the mean as a square with its 95 % interval, a note
// on the right; under a heading (what the rows share: condition, swarm size).
struct IntervalRow {
  QString heading, label, note;
  std::optional<double> mean, lo, hi;
};

// The queue's warnings (comparison_notes.txt) across the top of the plot area, over the two empty rows
// interval_plot leaves for it, in dark red on a white box: a figure shown without its folder still says
// what it compares.
void draw_note(QPainter& p, const Figure& f, const QString& note) {
  if (note.isEmpty()) return;
  const QFont small = font(13);
  const QRectF area = f.plot_area();
  const QStringList lines = wrapped("Note: " + note, small, area.width() - 16, 4);
  const double h = 18.0 * static_cast<double>(lines.size()) + 8;
  p.setPen(QPen(QColor(160, 0, 0), 1.5));
  p.setBrush(QColor(255, 255, 255, 230));
  p.drawRect(QRectF(area.left() + 4, area.top() + 4, area.width() - 8, h));
  p.setFont(small);
  for (qsizetype k = 0; k < lines.size(); ++k)
    p.drawText(QRectF(area.left() + 10, area.top() + 8 + 18.0 * static_cast<double>(k), area.width() - 20, 18), Qt::AlignLeft | Qt::AlignVCenter,
               lines[k]);
}

// Rows of estimates with their 95 % intervals against a dashed line at 0 (comparison.png, did.png),
// grouped under their headings in order of first appearance.
void interval_plot(const std::vector<IntervalRow>& given, const QString& title, const QString& x_label, const fs::path& file,
                   const QString& note = {}) {
  if (given.empty()) return;
  std::vector<IntervalRow> rows;
  std::vector<QString> headings;
  for (const auto& r : given)
    if (std::find(headings.begin(), headings.end(), r.heading) == headings.end()) headings.push_back(r.heading);
  for (const QString& h : headings) {
    rows.push_back({h, h + ":", "", {}, {}, {}});
    for (const auto& r : given)
      if (r.heading == h) rows.push_back({h, "    " + r.label, r.note, r.mean, r.lo, r.hi});
  }
  if (!note.isEmpty()) rows.insert(rows.begin(), 2, IntervalRow{});  // room for draw_note's box (4 lines at most)
  double lo = 0, hi = 0;
  for (const auto& r : rows)
    for (const auto& v : {r.mean, r.lo, r.hi})
      if (v) lo = std::min(lo, *v), hi = std::max(hi, *v);
  std::vector<QString> labels;
  for (const auto& r : rows) labels.push_back(r.label);
  const double pad = 0.05 * std::max(hi - lo, 1e-9);  // keeps 0 off the border
  lo -= pad, hi += pad;
  Figure f(title, plot_width, comparison_plot_height(rows.size()));
  f.x_axis(x_label, lo, hi);
  f.y_categories(labels);
  f.reserve_right(200);
  QPainter& p = f.begin();
  p.setPen(QPen(Qt::black, 1.5, Qt::DashLine));
  p.drawLine(QPointF(f.at(0, 0).x(), f.plot_area().top()), QPointF(f.at(0, 0).x(), f.plot_area().bottom()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const IntervalRow& r = rows[i];
    const double y = static_cast<double>(i);
    const QColor c = palette(0).darker(120);
    if (r.lo && r.hi) {
      p.setPen(QPen(c, 2.5));
      p.drawLine(f.at(*r.lo, y), f.at(*r.hi, y));
      p.drawLine(f.at(*r.lo, y) + QPointF(0, -7), f.at(*r.lo, y) + QPointF(0, 7));
      p.drawLine(f.at(*r.hi, y) + QPointF(0, -7), f.at(*r.hi, y) + QPointF(0, 7));
    }
    if (r.mean) {
      p.setPen(Qt::NoPen);
      p.setBrush(c);
      p.drawRect(QRectF(f.at(*r.mean, y) - QPointF(6, 6), QSizeF(12, 12)));
    }
  }
  p.setClipping(false);
  p.setPen(Qt::black);
  p.setFont(font(15));
  for (std::size_t i = 0; i < rows.size(); ++i)
    p.drawText(QRectF(f.plot_area().right() + 12, f.at(0, static_cast<double>(i)).y() - 11, 200, 22), Qt::AlignLeft | Qt::AlignVCenter, rows[i].note);
  draw_note(p, f, note);
  f.save(file);
}

QString text_of(std::string_view v) { return QString::fromUtf8(v.data(), static_cast<qsizetype>(v.size())); }

/// "dropout (drones → 14 at 200 s)"; a queue without conditions: "".
QString condition_words(const ConditionLabels& labels, const std::string& condition) {
  const auto it = labels.find(condition);
  return QString::fromStdString(condition + (it == labels.end() || it->second.empty() ? "" : " (" + it->second + ")"));
}
QString metric_words(const std::string& metric) { return QString::fromStdString(metric == "fraction_found" ? "targets found" : metric); }
/// Column `c` of the current row in the plot's unit: a fraction metric in percentage points.
std::optional<double> in_plot_unit(CsvReader& in, std::size_t c, const std::string& metric) {
  const auto v = in.optional_number(c);
  return v && metric.starts_with("fraction") ? std::optional(*v * 100) : v;
}

}  // namespace

QString comparison_note(const fs::path& out) {
  QFile file(QString::fromStdString((out / "comparison_notes.txt").string()));
  if (!file.open(QIODevice::ReadOnly)) return {};
  return QString::fromUtf8(file.readAll()).trimmed().replace('\n', ' ');
}

void forest(const fs::path& csv, const fs::path& file, const ConditionLabels& labels, const QString& note) {
  CsvReader in(csv);
  const std::size_t c_a = in.column("variant_a"), c_b = in.column("variant_b"), c_n = in.column("n"), c_mean = in.column("mean_diff"),
                    c_lo = in.column("ci_low"), c_hi = in.column("ci_high"), c_win = in.column("win_rate_a"),
                    c_drones = in.column("drones"), c_metric = in.column("metric");
  const auto c_condition = in.find("condition");
  std::vector<IntervalRow> rows;
  std::string metric;
  while (in.next()) {
    metric = std::string(in[c_metric]);
    auto scaled = [&](std::size_t c) { return in_plot_unit(in, c, metric); };
    const auto win = in.optional_number(c_win);
    const std::string condition(c_condition ? in[*c_condition] : std::string_view{});
    rows.push_back({(condition.empty() ? "" : condition_words(labels, condition) + ", ") + text_of(in[c_drones]) + " drones",
                    text_of(in[c_a]) + " − " + text_of(in[c_b]), "n = " + text_of(in[c_n]) + (win ? ", A higher in " + QString::number(*win * 100, 'f', 0) + " %" : QString()),
                    scaled(c_mean), scaled(c_lo), scaled(c_hi)});
  }
  const bool percent = metric.starts_with("fraction");
  interval_plot(rows, "Paired differences A − B in " + metric_words(metric) + " (mean, 95 % CI)",
                percent ? "difference A − B (percentage points)" : "difference A − B (" + QString::fromStdString(metric) + ")", file, note);
}

void draw_estimates(const std::vector<Estimate>& rows, const std::string& title, const std::string& x_label, const fs::path& file) {
  std::vector<IntervalRow> given;
  for (const Estimate& e : rows)
    given.push_back({QString::fromStdString(e.heading), QString::fromStdString(e.label), QString::fromStdString(e.note), e.mean, e.lo, e.hi});
  interval_plot(given, QString::fromStdString(title), QString::fromStdString(x_label), file);
}

void did_plot(const fs::path& csv, const fs::path& file, const ConditionLabels& labels, const QString& note) {
  CsvReader in(csv);
  const std::size_t c_a = in.column("variant_a"), c_b = in.column("variant_b"), c_base = in.column("baseline"), c_cond = in.column("condition"),
                    c_n = in.column("n"), c_did = in.column("did"), c_lo = in.column("ci_low"), c_hi = in.column("ci_high"),
                    c_drones = in.column("drones"), c_metric = in.column("metric");
  std::vector<IntervalRow> rows;
  std::string metric;
  while (in.next()) {
    metric = std::string(in[c_metric]);
    auto scaled = [&](std::size_t c) { return in_plot_unit(in, c, metric); };
    rows.push_back({condition_words(labels, std::string(in[c_cond])) + " against " + text_of(in[c_base]) + ", " + text_of(in[c_drones]) + " drones",
                    text_of(in[c_a]) + " − " + text_of(in[c_b]), "n = " + text_of(in[c_n]) + " repeats", scaled(c_did), scaled(c_lo), scaled(c_hi)});
  }
  const bool percent = metric.starts_with("fraction");
  interval_plot(rows, "How a condition changes A − B in " + metric_words(metric) + " (mean, 95 % CI)",
                percent ? "change of A − B (percentage points)" : "change of A − B (" + QString::fromStdString(metric) + ")", file, note);
}

}  // namespace salsa::plots
