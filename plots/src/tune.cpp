// The plots of a tune: convergence, each parameter against the score, the Pareto front.
#include "salsa/plots/tune.hpp"

#include <QPainterPath>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "salsa/plots/results.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;

namespace {

QString q(const std::string& s) { return QString::fromStdString(s); }

std::pair<double, double> span(const std::vector<double>& v) {
  double lo = 1e300, hi = -1e300;
  for (const double x : v)
    if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  if (lo > hi) return {0, 1};
  if (lo == hi) return {lo - 0.5, hi + 0.5};
  return {lo, hi};
}

void dot(Figure& f, double x, double y, const QColor& colour, double radius = 5) {
  f.painter().setPen(QPen(colour.darker(140), 1.2));
  f.painter().setBrush(colour);
  f.painter().drawEllipse(f.at(x, y), radius, radius);
}

const QColor candidate_colour(31, 119, 180), best_colour(214, 39, 40), defaults_colour(90, 90, 90);

void convergence(const fs::path& file, const TunePlot& p) {
  Figure f("Best " + q(p.objective) + " so far (" + (p.maximise ? "maximised" : "minimised") + ")", plot_width, plot_height);
  std::vector<double> x, y;
  for (const auto& [e, s] : p.best_so_far) x.push_back(e), y.push_back(s);
  std::vector<double> ys = y;
  if (std::isfinite(p.defaults)) ys.push_back(p.defaults);
  const auto [x0, x1] = span(x);
  const auto [y0, y1] = span(ys);
  f.x_axis("evaluations (tests run)", 0, x1 > x0 ? x1 : x0 + 1);
  f.y_axis(q(p.objective), y0, y1);
  f.legend({{LegendEntry::line, best_colour, "best so far"}, {LegendEntry::line, defaults_colour, "defaults"}});
  QPainter& painter = f.begin();
  if (std::isfinite(p.defaults)) {
    painter.setPen(QPen(defaults_colour, 2, Qt::DashLine));
    painter.drawLine(QPointF(f.plot_area().left(), f.at(0, p.defaults).y()), QPointF(f.plot_area().right(), f.at(0, p.defaults).y()));
  }
  QPainterPath path;  // a staircase: the best holds until the next improvement
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (i == 0) path.moveTo(f.at(x[i], y[i]));
    else path.lineTo(f.at(x[i], y[i - 1])), path.lineTo(f.at(x[i], y[i]));
  }
  if (!x.empty()) path.lineTo(f.at(x1, y.back()));
  painter.setBrush(Qt::NoBrush);
  painter.setPen(QPen(best_colour, 2.5));
  painter.drawPath(path);
  for (std::size_t i = 0; i < x.size(); ++i) dot(f, x[i], y[i], best_colour, 3.5);
  f.save(file);
}

void parameter(const fs::path& file, const TunePlot& p, const TunePlot::Parameter& param) {
  Figure f(q(p.objective) + " against " + q(param.key), plot_width, plot_height);
  std::vector<double> x = param.values;
  if (param.log)
    for (double& v : x) v = std::log10(v);
  const auto [x0, x1] = span(x);
  const auto [y0, y1] = span(p.scores);
  f.x_axis(param.log ? "log10 " + q(param.key) : q(param.key), x0, x1);
  f.y_axis(q(p.objective), y0, y1);
  f.legend({{LegendEntry::dot, candidate_colour, "candidate (every tuning world)"},
            {LegendEntry::ring, candidate_colour, "dropped by racing (estimate)"},
            {LegendEntry::dot, best_colour, "best"}});
  QPainter& painter = f.begin();
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (i == p.winner) continue;
    if (i < p.dropped.size() && p.dropped[i]) {
      painter.setPen(QPen(candidate_colour, 1.5));
      painter.setBrush(Qt::NoBrush);
      painter.drawEllipse(f.at(x[i], p.scores[i]), 4.5, 4.5);
    } else {
      dot(f, x[i], p.scores[i], candidate_colour);
    }
  }
  if (p.winner < x.size()) dot(f, x[p.winner], p.scores[p.winner], best_colour, 7);
  f.save(file);
}

void pareto(const fs::path& file, const TunePlot& p) {
  Figure f("Pareto front: " + q(p.objective) + " and " + q(p.second_objective), plot_width, plot_height);
  const auto [x0, x1] = span(p.scores);
  const auto [y0, y1] = span(p.second);
  f.x_axis(q(p.objective), x0, x1);
  f.y_axis(q(p.second_objective), y0, y1);
  f.legend({{LegendEntry::dot, candidate_colour, "candidate"}, {LegendEntry::line, best_colour, "Pareto front"}});
  QPainter& painter = f.begin();
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < p.scores.size(); ++i) {
    if (p.on_front[i]) front.push_back(i);
    else dot(f, p.scores[i], p.second[i], candidate_colour);
  }
  std::sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) { return p.scores[a] < p.scores[b]; });
  QPainterPath path;
  for (std::size_t k = 0; k < front.size(); ++k)
    k ? path.lineTo(f.at(p.scores[front[k]], p.second[front[k]])) : path.moveTo(f.at(p.scores[front[k]], p.second[front[k]]));
  painter.setBrush(Qt::NoBrush);
  painter.setPen(QPen(best_colour, 2));
  painter.drawPath(path);
  for (const std::size_t i : front) dot(f, p.scores[i], p.second[i], best_colour, 6);
  f.save(file);
}

}  // namespace

void draw_tune_plots(const fs::path& folder, const TunePlot& p) {
  fs::create_directories(folder);
  convergence(folder / "convergence.png", p);
  if (!p.scores.empty())
    for (const auto& param : p.parameters) parameter(folder / ("parameter_" + param.key + ".png"), p, param);
  if (!p.second.empty()) pareto(folder / "pareto.png", p);
}

}  // namespace salsa::plots
