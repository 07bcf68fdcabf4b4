// The plots of a queue (OUT/plots/): box plots, values over time with their intervals, targets found per swept parameter.
#include "salsa/plots/results.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>

#include "salsa/core/results/comparison.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "comparison_plots.hpp"
#include "plot_helpers.hpp"
#include "queue_rows.hpp"
#include "ranking_plots.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;
using nlohmann::json;

BoxStats box_stats(std::vector<double> v) {
  BoxStats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  auto quantile = [&](double q) {  // linear interpolation between order statistics
    const double at = q * static_cast<double>(v.size() - 1);
    const auto i = static_cast<std::size_t>(std::floor(at));
    return i + 1 < v.size() ? v[i] + (at - static_cast<double>(i)) * (v[i + 1] - v[i]) : v[i];
  };
  s.q1 = quantile(0.25), s.median = quantile(0.5), s.q3 = quantile(0.75);
  const double reach = 1.5 * (s.q3 - s.q1);
  s.low = s.q1, s.high = s.q3;
  for (double x : v) {
    if (x < s.q1 - reach || x > s.q3 + reach) s.outliers.push_back(x);
    else s.low = std::min(s.low, x), s.high = std::max(s.high, x);
  }
  return s;
}

namespace {

/// "dropout: drones → 14 at 200 s".
QString condition_text(const std::vector<QueueRow>& rows, const std::string& condition) {
  for (const auto& r : rows)
    if (r.condition == condition) return QString::fromStdString(condition + (r.condition_label.empty() ? "" : ": " + r.condition_label));
  return QString::fromStdString(condition);
}

/// A condition's line style: the first solid, then dashed, dotted...
Qt::PenStyle condition_style(std::size_t i) {
  constexpr Qt::PenStyle styles[] = {Qt::SolidLine, Qt::DashLine, Qt::DotLine, Qt::DashDotLine, Qt::DashDotDotLine};
  return styles[i % std::size(styles)];
}

/// Legend entries naming each condition by what it changes (none without conditions); without lines,
/// only those that say more than the name the axis shows.
void condition_notes(const std::vector<QueueRow>& rows, std::vector<LegendEntry>& legend, bool with_lines) {
  const auto conditions = conditions_of(rows);
  if (conditions.size() < 2 && conditions.front().empty()) return;
  for (std::size_t c = 0; c < conditions.size(); ++c)
    if (const QString text = condition_text(rows, conditions[c]); with_lines || text != QString::fromStdString(conditions[c]))
      legend.push_back({with_lines ? LegendEntry::line : LegendEntry::note, QColor(90, 90, 90), text, condition_style(c)});
}

void box_plot(const std::vector<QueueRow>& rows, const fs::path& file) {
  const auto variants = variants_of(rows);
  const auto sizes = sizes_of(rows);
  const auto conditions = conditions_of(rows);
  const bool by_condition = conditions.size() > 1;
  // One category per swarm size and condition.
  std::vector<std::pair<std::string, std::string>> categories;
  std::vector<QString> names;
  for (const auto& s : sizes)
    for (const auto& c : conditions) {
      categories.emplace_back(s, c);
      names.push_back(QString::fromStdString(!by_condition ? s : sizes.size() > 1 ? s + " · " + c : c));
    }
  Figure f(by_condition ? "Targets found per behavior, swarm size and condition" : "Targets found per behavior and swarm size", plot_width, plot_height);
  f.x_categories(!by_condition ? "swarm size (drones)" : sizes.size() > 1 ? "swarm size (drones) · condition" : "condition (" + QString::fromStdString(sizes.front()) + " drones)", names);
  double lo = 100, hi = 0;
  for (const auto& r : rows) lo = std::min(lo, r.found), hi = std::max(hi, r.found);
  f.y_axis("targets found at the end (%)", std::max(0.0, lo - 5), std::min(100.0, hi + 5));
  std::vector<LegendEntry> legend;
  for (std::size_t v = 0; v < variants.size(); ++v) legend.push_back({LegendEntry::box, palette(v), QString::fromStdString(variants[v])});
  legend.push_back({LegendEntry::ring, Qt::black, "outlier (beyond 1.5 IQR)"});
  condition_notes(rows, legend, false);
  f.legend(legend);
  QPainter& p = f.begin();
  const double slot = 0.8 / static_cast<double>(variants.size());  // of a category's width
  const double half = slot * 0.35 * f.plot_area().width() / static_cast<double>(categories.size());
  for (std::size_t s = 0; s < categories.size(); ++s)
    for (std::size_t v = 0; v < variants.size(); ++v) {
      std::vector<double> values;
      for (const auto& r : rows)
        if (r.drones == categories[s].first && r.condition == categories[s].second && r.variant == variants[v]) values.push_back(r.found);
      if (values.empty()) continue;
      const BoxStats b = box_stats(values);
      const double cx = static_cast<double>(s) - 0.4 + slot * (static_cast<double>(v) + 0.5);
      const double x = f.at(cx, 0).x();
      const QColor c = palette(v);
      p.setPen(QPen(c.darker(160), 1.8));
      p.drawLine(QPointF(x, f.at(0, b.low).y()), QPointF(x, f.at(0, b.q1).y()));
      p.drawLine(QPointF(x, f.at(0, b.q3).y()), QPointF(x, f.at(0, b.high).y()));
      p.drawLine(QPointF(x - half / 2, f.at(0, b.low).y()), QPointF(x + half / 2, f.at(0, b.low).y()));
      p.drawLine(QPointF(x - half / 2, f.at(0, b.high).y()), QPointF(x + half / 2, f.at(0, b.high).y()));
      p.setBrush(c);
      p.drawRect(QRectF(QPointF(x - half, f.at(0, b.q3).y()), QPointF(x + half, f.at(0, b.q1).y())));
      p.setPen(QPen(Qt::black, 3));
      p.drawLine(QPointF(x - half, f.at(0, b.median).y()), QPointF(x + half, f.at(0, b.median).y()));
      p.setPen(QPen(c.darker(160), 1.8));
      p.setBrush(Qt::NoBrush);
      for (double o : b.outliers) p.drawEllipse(QPointF(x, f.at(0, o).y()), 4.5, 4.5);
    }
  f.save(file);
}

// A column of the tests' summary.csv drawn over time per variant; `optional`: tests without it are left out.
struct Measure {
  const char* column;
  double scale;
  std::optional<double> top;  // the largest value there can be, else the largest a repeat had
  bool optional;
  const char* title;  // "<title>, N drones (…)"
  QString y_label;
  std::string file;  // "<file>_<N>_drones.png"
};
const Measure found_measure{"fraction_found", 100, 100.0, false, "Targets found over time", "targets found (%)", "found_over_time"};
const Measure alive_measure{"alive", 1, std::nullopt, true, "Drones alive over time", "drones flying", "alive_over_time"};

/// The mean of the repeats' values and the half width of its 95 % t-interval (0 for a single value).
std::pair<double, double> mean_and_half_width(const std::vector<double>& values) {
  const double n = static_cast<double>(values.size());
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double ss = 0;
  for (double x : values) ss += (x - mean) * (x - mean);
  return {mean, values.size() > 1 ? t_half_width(values.size(), std::sqrt(ss / (n - 1))) : 0};
}

/// The times of a test's timed changes (config.json's "changes"; none without config.json).
std::vector<double> change_times(const fs::path& folder) {
  std::vector<double> out;
  if (!is_file(folder / "config.json")) return out;
  const json config = read_json(folder / "config.json", "a test's config.json");
  if (config.is_object() && config.contains("changes") && config["changes"].is_array())
    for (const json& c : config["changes"])
      if (c.is_object() && c.contains("time") && c["time"].is_number()) out.push_back(c["time"].get<double>());
  return out;
}

// The mean of a measure over time per variant and condition (colour: variant; line style: condition) with
// a 95 % t-interval over the repeats, for one swarm size; a dashed vertical line at each timed change.
void over_time(const fs::path& out, const std::vector<QueueRow>& rows, const std::string& size, const Measure& m) {
  const auto variants = variants_of(rows);
  const auto conditions = conditions_of(rows);
  struct Mean { std::vector<double> time, mean, lo, hi; };
  struct Drawn { std::size_t variant, condition; Mean mean; };
  std::vector<Drawn> lines;
  std::map<double, std::set<std::size_t>> changes;  // time → the conditions with a change then
  double t0 = 1e300, t1 = -1e300, top = 0;
  for (std::size_t c = 0; c < conditions.size(); ++c)
    for (std::size_t v = 0; v < variants.size(); ++v) {
      std::map<double, std::vector<double>> at;  // time → the value of each repeat
      for (const auto& r : rows) {
        if (r.drones != size || r.variant != variants[v] || r.condition != conditions[c]) continue;
        CsvReader in(out / r.name / "summary.csv");
        if (m.optional && !in.find(m.column)) continue;
        const std::size_t c_time = in.column("time"), c_value = in.column(m.column);
        while (in.next()) at[in.number(c_time)].push_back(in.number(c_value) * m.scale);
        for (double t : change_times(out / r.name)) changes[t].insert(c);
      }
      if (at.empty()) continue;
      double highest = 0;
      for (const auto& [time, values] : at) highest = std::max(highest, *std::max_element(values.begin(), values.end()));
      Mean l;
      for (const auto& [time, values] : at) {
        const auto [mean, half] = mean_and_half_width(values);
        l.time.push_back(time), l.mean.push_back(mean), l.lo.push_back(std::max(0.0, mean - half)), l.hi.push_back(std::min(m.top.value_or(highest), mean + half));
        t0 = std::min(t0, time), t1 = std::max(t1, time), top = std::max(top, l.hi.back());
      }
      lines.push_back({v, c, std::move(l)});
    }
  if (lines.empty()) return;
  Figure f(QString(m.title) + ", " + QString::fromStdString(size) + " drones (mean, 95 % CI over repeats)", plot_width, plot_height);
  f.x_axis("simulated time (s)", t0, t1);
  f.y_axis(m.y_label, 0, m.top.value_or(top * 1.04));  // room above a flat line at the top
  std::vector<LegendEntry> legend;
  std::set<std::size_t> shown;
  for (const auto& l : lines)
    if (shown.insert(l.variant).second) legend.push_back({LegendEntry::line, palette(l.variant), QString::fromStdString(variants[l.variant])});
  legend.push_back({LegendEntry::band, QColor(0, 0, 0, 40), "95 % confidence interval"});
  condition_notes(rows, legend, true);
  // Black and dash-dot-dot, named as vertical: apart from the conditions' grey line styles.
  const QPen change_pen(QColor(30, 30, 30), 1.2, Qt::DashDotDotLine);
  if (!changes.empty()) legend.push_back({LegendEntry::line, change_pen.color(), "a timed change (vertical line)", change_pen.style()});
  f.legend(legend);
  QPainter& p = f.begin();
  for (const auto& l : lines) {
    QColor band = palette(l.variant);
    band.setAlpha(conditions.size() > 1 ? 35 : 55);
    draw_band(f, l.mean.time, l.mean.lo, l.mean.hi, band);
  }
  for (const auto& l : lines) draw_line(f, l.mean.time, l.mean.mean, palette(l.variant), 2.5, condition_style(l.condition));
  // Each change time once, named by the conditions that change then (all of them: no names).
  p.setFont(font(14));
  for (const auto& [time, which] : changes) {
    const double x = f.at(time, 0).x();
    p.setPen(change_pen);
    p.drawLine(QPointF(x, f.plot_area().top()), QPointF(x, f.plot_area().bottom()));
    QString names;
    if (which.size() < conditions.size())
      for (std::size_t c : which) names += (names.isEmpty() ? "" : ", ") + QString::fromStdString(conditions[c]);
    p.setPen(QColor(80, 80, 80));
    p.drawText(QRectF(x + 5, f.plot_area().top() + 4, 400, 20), Qt::AlignLeft | Qt::AlignTop,
               (names.isEmpty() ? QString() : names + ": ") + "change at " + QString::number(time, 'g', 6) + " s");
  }
  f.save(out / "plots" / (m.file + "_" + size + "_drones.png"));
}

// found_vs_<behavior>_<p>.png: for each behavior parameter the queue sweeps, targets found against its
// value (mean and 95 % interval over the repeats), a line per condition, swarm size and value of the
// behavior's other swept parameters.
void score_plots(const std::vector<QueueRow>& rows, const fs::path& dir) {
  const auto sizes = sizes_of(rows);
  for (const std::string& behavior : in_order(rows, &QueueRow::behavior)) {
    std::map<std::string, std::set<double>> values;  // parameter → its values among the behavior's tests
    for (const auto& r : rows)
      if (r.behavior == behavior)
        for (const auto& [p, v] : r.params) values[p].insert(v);
    for (const auto& [param, xs] : values) {
      if (xs.size() < 2) continue;
      // A line per (condition, size, the other swept parameters), points by value.
      std::map<std::string, std::map<double, std::vector<double>>> lines;
      std::vector<std::string> order;
      for (const auto& r : rows) {
        if (r.behavior != behavior || !r.params.count(param)) continue;
        std::string key = r.condition;
        if (sizes.size() > 1) key += (key.empty() ? "" : ", ") + r.drones + " drones";
        for (const auto& [other, v] : r.params)
          if (other != param && values[other].size() > 1) key += (key.empty() ? "" : ", ") + other + " = " + Parameter::format(v);
        if (!lines.count(key)) order.push_back(key);
        lines[key][r.params.at(param)].push_back(r.found);
      }
      std::sort(order.begin(), order.end(), [](const std::string& a, const std::string& b) { return natural_less(a, b); });
      Figure f("Targets found against " + QString::fromStdString(param) + " (" + QString::fromStdString(behavior) + "; mean, 95 % CI over repeats)",
               plot_width, plot_height);
      // A switch (its values 0 and 1 alone) is two categories, not a number line with 0.2, 0.4, …
      const bool flag = xs == std::set<double>{0, 1};
      const double span = flag ? 3 : *xs.rbegin() - *xs.begin();  // the dodge below: 3 % of a category
      if (flag)
        f.x_categories(QString::fromStdString(behavior + "." + param), {QString::fromStdString(param + " = 0"), QString::fromStdString(param + " = 1")});
      else
        f.x_axis(QString::fromStdString(behavior + "." + param), *xs.begin() - 0.03 * span, *xs.rbegin() + 0.03 * span);
      double lo = 100, hi = 0;
      struct Point { double x, mean, lo, hi; };
      std::vector<std::vector<Point>> drawn;
      for (const std::string& key : order) {
        std::vector<Point>& points = drawn.emplace_back();
        for (const auto& [x, found] : lines[key]) {
          const auto [mean, half] = mean_and_half_width(found);
          points.push_back({x, mean, std::max(0.0, mean - half), std::min(100.0, mean + half)});
          lo = std::min(lo, points.back().lo), hi = std::max(hi, points.back().hi);
        }
      }
      f.y_axis("targets found at the end (%)", std::max(0.0, lo - 5), std::min(100.0, hi + 5));
      std::vector<LegendEntry> legend;
      for (std::size_t k = 0; k < order.size(); ++k)
        legend.push_back({LegendEntry::line, palette(k), order[k].empty() ? QString("mean, 95 % CI") : QString::fromStdString(order[k])});
      f.legend(legend);
      QPainter& p = f.begin();
      for (std::size_t k = 0; k < drawn.size(); ++k) {
        // Lines side by side by 1 % of the axis, so that their intervals at one value do not hide each other.
        const double dodge = 0.01 * span * (static_cast<double>(k) - static_cast<double>(drawn.size() - 1) / 2);
        for (Point& pt : drawn[k]) pt.x += dodge;
        std::vector<double> x, mean;
        for (const Point& pt : drawn[k]) x.push_back(pt.x), mean.push_back(pt.mean);
        draw_line(f, x, mean, palette(k), 2);
        p.setPen(QPen(palette(k).darker(130), 2));
        p.setBrush(palette(k));
        for (const Point& pt : drawn[k]) {
          p.drawLine(f.at(pt.x, pt.lo), f.at(pt.x, pt.hi));
          p.drawLine(f.at(pt.x, pt.lo) + QPointF(-6, 0), f.at(pt.x, pt.lo) + QPointF(6, 0));
          p.drawLine(f.at(pt.x, pt.hi) + QPointF(-6, 0), f.at(pt.x, pt.hi) + QPointF(6, 0));
          p.drawEllipse(f.at(pt.x, pt.mean), 5, 5);
        }
      }
      f.save(dir / ("found_vs_" + behavior + "_" + param + ".png"));
    }
  }
}

}  // namespace

void draw_queue_plots(const fs::path& out) {
  ConditionLabels labels;
  const std::vector<QueueRow> rows = read_queue_rows(out, &labels);
  const fs::path dir = out / "plots";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(name_of(dir) + ": cannot create folder (" + ec.message() + ")");
  if (rows.empty()) return;
  box_plot(rows, dir / "found_boxplot.png");
  for (const auto& size : sizes_of(rows))
    for (const Measure* m : {&found_measure, &alive_measure}) over_time(out, rows, size, *m);
  const QString note = comparison_note(out);
  if (is_file(out / "comparison.csv")) forest(out / "comparison.csv", dir / "comparison.png", labels, note);
  if (is_file(out / "did.csv")) did_plot(out / "did.csv", dir / "did.png", labels, note);
  score_plots(rows, dir);
  if (is_file(out / "ranking.csv")) ranking_plots(out, variants_of(rows), labels);
}

}  // namespace salsa::plots
