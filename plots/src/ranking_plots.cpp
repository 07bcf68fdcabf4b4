// The queue's ranking plots, from ranking.csv: ranking.png (each cell and condition's variants by rank
// with their 95 % intervals) and, when the conditions differ in one number, by_<key>.png (each
// variant's mean against that number).
#include "ranking_plots.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "salsa/core/files/csv_reader.hpp"
#include "figure.hpp"
#include "plot_helpers.hpp"
#include "salsa/plots/results.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;

namespace {

/// One variant of ranking.csv, in the plot's unit (a fraction metric in %).
struct Ranked {
  std::string cell, condition, drones, variant, rank, differs;
  double mean = 0;
  std::optional<double> lo, hi, best_share;
};

std::vector<Ranked> read_ranking(const fs::path& csv, std::string& metric) {
  CsvReader in(csv);
  const std::size_t c_cell = in.column("cell"), c_condition = in.column("condition"), c_drones = in.column("drones"), c_metric = in.column("metric"),
                    c_rank = in.column("rank"), c_variant = in.column("variant"), c_mean = in.column("mean"), c_lo = in.column("ci_low"),
                    c_hi = in.column("ci_high"), c_share = in.column("best_share"), c_differs = in.column("differs_from_best");
  std::vector<Ranked> out;
  while (in.next()) {
    metric = std::string(in[c_metric]);
    const double scale = metric.starts_with("fraction") ? 100 : 1;
    auto scaled = [&](std::size_t c) {
      const auto v = in.optional_number(c);
      return v ? std::optional(*v * scale) : v;
    };
    out.push_back({std::string(in[c_cell]), std::string(in[c_condition]), std::string(in[c_drones]), std::string(in[c_variant]),
                   std::string(in[c_rank]), std::string(in[c_differs]), in.number(c_mean) * scale, scaled(c_lo), scaled(c_hi),
                   in.optional_number(c_share)});
  }
  return out;
}

QString metric_axis(const std::string& metric) {
  return metric == "fraction_found" ? QString("targets found at the end (%)")
                                    : QString::fromStdString(metric) + (metric.starts_with("fraction") ? " (%)" : "");
}

/// "dropout (drones → 14 at 200 s)"; "" without conditions.
QString condition_words(const ConditionLabels& labels, const std::string& condition) {
  const auto it = labels.find(condition);
  return QString::fromStdString(condition + (it == labels.end() || it->second.empty() ? "" : " (" + it->second + ")"));
}

void ranking_plot(const std::vector<Ranked>& ranked, const std::string& metric, const ConditionLabels& labels, const fs::path& file) {
  // Under a heading per condition and cell (its rows already in rank order), a row per variant.
  struct Row {
    QString label, note;
    const Ranked* r = nullptr;  // null: a heading
  };
  std::vector<Row> rows;
  std::string last;
  for (const Ranked& r : ranked) {
    if (const std::string group = r.cell + '\n' + r.condition; group != last) {
      last = group;
      const QString condition = condition_words(labels, r.condition);
      rows.push_back({(condition.isEmpty() ? "" : condition + ", ") + QString::fromStdString(r.drones) + " drones:", "", nullptr});
    }
    QString note = r.best_share ? "best in " + QString::number(*r.best_share * 100, 'f', 0) + " %" : QString("best in –");
    if (r.differs == "yes") note += ", below #1";
    rows.push_back({"    " + QString::fromStdString(r.rank + ". " + r.variant), note, &r});
  }
  double lo = 1e300, hi = -1e300;
  for (const Ranked& r : ranked)
    for (const auto& v : {std::optional(r.mean), r.lo, r.hi})
      if (v) lo = std::min(lo, *v), hi = std::max(hi, *v);
  const double pad = 0.05 * std::max(hi - lo, 1e-9);
  std::vector<QString> names;
  for (const Row& r : rows) names.push_back(r.label);
  Figure f("Variants ranked by mean " + QString::fromStdString(metric == "fraction_found" ? "targets found" : metric) + " (mean, 95 % CI; grey: below #1)", plot_width,
           comparison_plot_height(rows.size()));
  f.x_axis(metric_axis(metric), lo - pad, hi + pad);
  f.y_categories(names);
  f.reserve_right(200);
  // #1 dark, those its paired interval puts below it grey (the note says so too).
  const QColor best = palette(0).darker(130), level = palette(0), below(150, 150, 150);
  QPainter& p = f.begin();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Ranked* r = rows[i].r;
    if (!r) continue;
    const double y = static_cast<double>(i);
    const QColor c = r->differs.empty() && r->rank == "1" ? best : r->differs == "yes" ? below : level;
    if (r->lo && r->hi) {
      p.setPen(QPen(c, 2.5));
      p.drawLine(f.at(*r->lo, y), f.at(*r->hi, y));
      p.drawLine(f.at(*r->lo, y) + QPointF(0, -7), f.at(*r->lo, y) + QPointF(0, 7));
      p.drawLine(f.at(*r->hi, y) + QPointF(0, -7), f.at(*r->hi, y) + QPointF(0, 7));
    }
    p.setPen(Qt::NoPen);
    p.setBrush(c);
    p.drawRect(QRectF(f.at(r->mean, y) - QPointF(6, 6), QSizeF(12, 12)));
  }
  p.setClipping(false);
  p.setPen(Qt::black);
  p.setFont(font(15));
  for (std::size_t i = 0; i < rows.size(); ++i)
    p.drawText(QRectF(f.plot_area().right() + 12, f.at(0, static_cast<double>(i)).y() - 11, 200, 22), Qt::AlignLeft | Qt::AlignVCenter, rows[i].note);
  f.save(file);
}

void by_number_plot(const std::vector<Ranked>& ranked, const std::string& metric, const ConditionNumber& number,
                    const std::vector<std::string>& variants, const fs::path& file) {
  // A line per variant and cell: colour by variant, line style by cell.
  std::vector<std::string> cells, drones;
  for (const Ranked& r : ranked)
    if (std::find(cells.begin(), cells.end(), r.cell) == cells.end()) cells.push_back(r.cell), drones.push_back(r.drones);
  const bool drones_differ = std::set<std::string>(drones.begin(), drones.end()).size() == cells.size();
  std::map<std::pair<std::size_t, std::size_t>, std::vector<const Ranked*>> lines;  // (variant, cell) → points
  double lo = 1e300, hi = -1e300;
  for (const Ranked& r : ranked) {
    const auto v = std::find(variants.begin(), variants.end(), r.variant);
    const auto x = number.values.find(r.condition);
    if (v == variants.end() || x == number.values.end()) continue;
    lines[{static_cast<std::size_t>(v - variants.begin()), static_cast<std::size_t>(std::find(cells.begin(), cells.end(), r.cell) - cells.begin())}]
        .push_back(&r);
    for (const auto& y : {std::optional(r.mean), r.lo, r.hi})
      if (y) lo = std::min(lo, *y), hi = std::max(hi, *y);
  }
  if (lines.empty()) return;
  double x0 = 1e300, x1 = -1e300;
  for (const auto& [condition, x] : number.values) x0 = std::min(x0, x), x1 = std::max(x1, x);
  const double span = std::max(x1 - x0, 1e-9), pad = 0.05 * std::max(hi - lo, 1e-9);
  Figure f(QString::fromStdString(metric == "fraction_found" ? "Targets found" : metric) + " against " + QString::fromStdString(number.key) +
               " (mean, 95 % CI over repeats)",
           plot_width, plot_height);
  f.x_axis(QString::fromStdString(number.key), x0 - 0.04 * span, x1 + 0.04 * span);
  f.y_axis(metric_axis(metric), lo - pad, hi + pad);
  constexpr Qt::PenStyle styles[] = {Qt::SolidLine, Qt::DashLine, Qt::DotLine, Qt::DashDotLine, Qt::DashDotDotLine};
  std::vector<LegendEntry> legend;
  std::set<std::size_t> shown;
  for (const auto& [key, points] : lines)
    if (shown.insert(key.first).second) legend.push_back({LegendEntry::line, palette(key.first), QString::fromStdString(variants[key.first])});
  if (cells.size() > 1)
    for (std::size_t c = 0; c < cells.size(); ++c)
      legend.push_back({LegendEntry::line, QColor(90, 90, 90), QString::fromStdString(drones_differ ? drones[c] + " drones" : "cell " + cells[c]),
                        styles[c % std::size(styles)]});
  f.legend(legend);
  QPainter& p = f.begin();
  std::size_t k = 0;
  for (auto& [key, points] : lines) {
    // Lines side by side by 1 % of the axis, so that their intervals at one value do not hide each other.
    const double dodge = 0.01 * span * (static_cast<double>(k++) - static_cast<double>(lines.size() - 1) / 2);
    std::sort(points.begin(), points.end(), [&](const Ranked* a, const Ranked* b) { return number.values.at(a->condition) < number.values.at(b->condition); });
    std::vector<double> xs, ys;
    for (const Ranked* r : points) xs.push_back(number.values.at(r->condition) + dodge), ys.push_back(r->mean);
    const QColor c = palette(key.first);
    draw_line(f, xs, ys, c, 2, styles[key.second % std::size(styles)]);
    p.setPen(QPen(c.darker(130), 2));
    p.setBrush(c);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (points[i]->lo && points[i]->hi) {
        p.drawLine(f.at(xs[i], *points[i]->lo), f.at(xs[i], *points[i]->hi));
        p.drawLine(f.at(xs[i], *points[i]->lo) + QPointF(-6, 0), f.at(xs[i], *points[i]->lo) + QPointF(6, 0));
        p.drawLine(f.at(xs[i], *points[i]->hi) + QPointF(-6, 0), f.at(xs[i], *points[i]->hi) + QPointF(6, 0));
      }
      p.drawEllipse(f.at(xs[i], ys[i]), 5, 5);
    }
  }
  f.save(file);
}

}  // namespace

std::optional<ConditionNumber> condition_number(const fs::path& out) {
  CsvReader in(out / "summary.csv");
  const std::size_t c_status = in.column("status");
  const auto c_condition = in.find("condition"), c_drones = in.find("drones");
  if (!c_condition || !c_drones) return std::nullopt;
  // The inputs (drones up to the outcome's columns) but the behavior's, which the variants differ in.
  std::vector<std::size_t> inputs;
  for (std::size_t c = *c_drones; c < in.header().size() && !in.header()[c].starts_with("outcome."); ++c) {
    const std::string& h = in.header()[c];
    const bool behavior = h == "behavior" || h.starts_with("behavior.") || h.starts_with("versions.") ||
                          (h.starts_with("groups.") && (h.ends_with(".behavior") || h.find(".behavior.") != std::string::npos));
    if (!behavior) inputs.push_back(c);
  }
  std::vector<std::map<std::string, std::set<std::string>>> seen(inputs.size());  // per input: condition → its values
  while (in.next())
    if (in[c_status] == "ok")
      for (std::size_t k = 0; k < inputs.size(); ++k) seen[k][std::string(in[*c_condition])].emplace(in[inputs[k]]);
  std::optional<ConditionNumber> found;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (seen[k].size() < 2) return std::nullopt;  // fewer than two conditions
    std::set<std::string> all;
    bool one_each = true;
    for (const auto& [condition, values] : seen[k]) one_each = one_each && values.size() == 1, all.insert(values.begin(), values.end());
    if (!one_each || all.size() < 2) continue;  // not what a condition sets
    if (found) return std::nullopt;              // a second setting differs between the conditions
    ConditionNumber n{in.header()[inputs[k]], {}};
    for (const auto& [condition, values] : seen[k]) {
      const std::string& text = *values.begin();
      double x = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
      if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x)) return std::nullopt;
      n.values[condition] = x;
    }
    found = std::move(n);
  }
  return found;
}

void ranking_plots(const fs::path& out, const std::vector<std::string>& variants, const ConditionLabels& labels) {
  std::string metric;
  const std::vector<Ranked> ranked = read_ranking(out / "ranking.csv", metric);
  if (ranked.empty()) return;
  ranking_plot(ranked, metric, labels, out / "plots" / "ranking.png");
  if (const auto number = condition_number(out)) by_number_plot(ranked, metric, *number, variants, out / "plots" / ("by_" + number->key + ".png"));
}

}  // namespace salsa::plots
