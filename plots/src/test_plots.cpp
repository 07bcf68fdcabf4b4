// The plots of one test (TEST/plots/): values over time, the drones' trajectories, a heat map of where they were, speeds.
#include "salsa/plots/results.hpp"

#include <QPolygonF>

#include <algorithm>
#include <cmath>
#include <optional>

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "marks.hpp"  // the desktop's marks, drawn alike here
#include "plot_helpers.hpp"
#include "test_data.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;

int HeatGrid::index_of(double x, double y) const {
  const double cx = std::floor((x - area.x0) / cell), cy = std::floor((y - area.y0) / cell);
  if (!(cx >= 0 && cx < columns && cy >= 0 && cy < rows)) return -1;
  return static_cast<int>(cy) * columns + static_cast<int>(cx);
}

HeatGrid bin_positions(const Points& positions, const Rect& area, int columns) {
  HeatGrid g;
  g.area = area;
  g.columns = std::max(1, columns);
  g.cell = (area.x1 - area.x0) / g.columns;
  g.rows = std::max(1, static_cast<int>(std::ceil((area.y1 - area.y0) / g.cell - 1e-9)));
  g.values.assign(static_cast<std::size_t>(g.columns * g.rows), 0.0);
  for (auto [x, y] : positions)
    if (const int i = g.index_of(x, y); i >= 0 && y <= area.y1) ++g.values[static_cast<std::size_t>(i)];
  const double top = *std::max_element(g.values.begin(), g.values.end());
  if (top > 0)
    for (double& v : g.values) v = v * 100 / top;
  return g;
}

namespace {

// Values over time, a line each, the first at the bottom and at the top of the legend; a single line
// has no legend.
struct Line {
  QString name;
  const std::vector<double>* y;
  QColor colour;
  double width = 2.5;
};

void time_chart(const TestData& t, const std::vector<Line>& lines, const QString& title, const QString& y_label,
                std::optional<std::pair<double, double>> y_range, const fs::path& file) {
  Figure f(QString::fromStdString(t.name) + ": " + title, plot_width, plot_height);
  const auto [t0, t1] = range_of(t.time);
  f.x_axis("simulated time (s)", t0, t1);
  const auto [lo, hi] = y_range ? *y_range : range_of(*lines.front().y);
  f.y_axis(y_label, std::min(0.0, lo), hi);
  if (lines.size() > 1) {
    std::vector<LegendEntry> legend;
    for (const Line& l : lines) legend.push_back({LegendEntry::line, l.colour, l.name});
    f.legend(legend);
  }
  f.begin();
  for (const Line& l : lines) draw_line(f, t.time, *l.y, l.colour, l.width);
  f.save(file);
}

// One summary.csv column over time; with the groups' columns, the total is a wide grey line under a
// line per group (a group that did it all covers the total's middle, not all of it).
std::vector<Line> per_group(const TestData& t, const std::vector<double>& total, std::vector<double> Group::*column) {
  std::vector<Line> lines{{"all drones", &total, palette(0)}};
  for (std::size_t g = 0; g < t.groups.size(); ++g)
    if ((t.groups[g].*column).size() == t.time.size())
      lines.push_back({QString::fromStdString(t.groups[g].name), &(t.groups[g].*column), group_colour(g)});
  if (lines.size() > 1) lines[0].colour = QColor(150, 150, 150), lines[0].width = 6;
  return lines;
}

// Obstacles opaque (drawn before targets and paths, so nothing hides under them unseen).
const QColor obstacle_colour(150, 150, 150);

void draw_map(Figure& f, const MapShape& m) {
  QPainter& p = f.painter();
  auto mapped = [&](const QPolygonF& poly) {
    QPolygonF out;
    for (const QPointF& q : poly) out << f.at(q.x(), q.y());
    return out;
  };
  p.setPen(QPen(QColor(90, 90, 90), 1.2));
  p.setBrush(obstacle_colour);
  for (const auto& poly : m.solid) p.drawPolygon(mapped(poly));
  p.setBrush(Qt::NoBrush);
  p.setPen(QPen(QColor(90, 90, 90), 2.5));
  for (const auto& poly : m.hollow) p.drawPolygon(mapped(poly));
  for (const auto& line : m.lines) p.drawPolyline(mapped(line));
  if (m.bounds) {
    p.setPen(QPen(Qt::black, 3));
    p.drawRect(QRectF(f.at(m.bounds->x0, m.bounds->y1), f.at(m.bounds->x1, m.bounds->y0)));
  }
}

std::vector<LegendEntry> map_legend(const MapShape& m) {
  std::vector<LegendEntry> e;
  if (!m.solid.empty()) e.push_back({LegendEntry::square, obstacle_colour, "obstacle"});
  if (!m.bounds) e.push_back({LegendEntry::note, Qt::black, "(map geometry not in the folder)"});
  return e;
}

// Targets are light (pastel) discs under the paths, so thousands of them never hide a path: found
// ones green, the ones not found red, drawn last (they are the interesting ones).
const QColor found_colour(172, 222, 172), missed_colour(245, 140, 125);

QString metres(double v) { return QString::number(v, 'g', 4) + " m"; }

void trajectories(const TestData& t, const fs::path& file) {
  Figure f(QString::fromStdString(t.name) + ": drone trajectories", plot_width, plot_height);
  f.x_axis("x (m)", t.view.x0, t.view.x1, true);
  f.y_axis("y (m)", t.view.y0, t.view.y1, true);
  f.equal_aspect();
  auto legend = map_legend(t.map);
  if (t.by_group())
    for (std::size_t g = 0; g < t.groups.size(); ++g) {
      const auto n = std::count_if(t.paths.begin(), t.paths.end(), [&](const auto& path) { return path.first.first == g; });
      legend.push_back({LegendEntry::line, group_colour(g), QString::fromStdString(t.groups[g].name) + " (" + QString::number(n) + " drones)"});
    }
  else
    legend.push_back({LegendEntry::line, palette(0).darker(165), "drone paths (" + QString::number(t.paths.size()) + ", one colour each)"});
  if (!t.stops.empty()) {
    const auto failed = std::count_if(t.stops.begin(), t.stops.end(), [](const auto& s) { return s.second.failed; });
    const auto landed = static_cast<long>(t.stops.size()) - failed;
    legend.push_back({LegendEntry::cross, QColor(60, 60, 60), "where a drone stopped (" +
                      (landed ? QString::number(landed) + " landed" + (failed ? ", " : "") : QString()) +
                      (failed ? QString::number(failed) + " failed" : QString()) + ")"});
  }
  legend.push_back({LegendEntry::dot, found_colour, "target found (" + QString::number(t.targets_found.size()) + ")"});
  legend.push_back({LegendEntry::dot, missed_colour, "target not found (" + QString::number(t.targets_missed.size()) + ")"});
  if (t.target_radius > 0 && !(t.targets_found.empty() && t.targets_missed.empty()))
    legend.push_back({LegendEntry::note, Qt::black, "(targets to scale: radius " + metres(t.target_radius) + ")"});
  f.legend(legend);
  QPainter& p = f.begin();
  draw_map(f, t.map);

  // Targets at their size (at least 1 pixel across the radius; 3 pixels when the size is unknown),
  // outlined only when large enough for an outline to show.
  const double radius = t.target_radius > 0 ? std::max(1.0, t.target_radius * f.pixels_per_x()) : 3.0;
  for (const auto& [points, colour] : {std::pair{&t.targets_found, found_colour}, std::pair{&t.targets_missed, missed_colour}}) {
    p.setPen(radius >= 3 ? QPen(colour.darker(135), 1) : QPen(Qt::NoPen));
    p.setBrush(colour);
    for (auto [x, y] : *points) p.drawEllipse(f.at(x, y), radius, radius);
  }

  // Paths on top: points within 1.5 pixels of the last one drawn are skipped (millions of rows; a
  // line is 1.5 pixels wide, so nothing visible is lost). Drones in id order, so the last group does
  // not cover the others; a drone's colour is its group's, else a dark one of its own.
  std::vector<const std::pair<const TestData::DroneKey, Points>*> drones;
  for (const auto& drone : t.paths) drones.push_back(&drone);
  std::stable_sort(drones.begin(), drones.end(), [](auto a, auto b) { return a->first.second < b->first.second; });
  auto colour = [&](std::size_t k) { return t.by_group() ? group_colour(drones[k]->first.first) : palette(k).darker(165); };
  const double min_step = 1.5 / f.pixels_per_x();
  for (std::size_t k = 0; k < drones.size(); ++k) {
    QPolygonF line;
    double lx = 1e300, ly = 1e300;
    for (auto [x, y] : drones[k]->second)
      if (std::abs(x - lx) + std::abs(y - ly) >= min_step) line << f.at(x, y), lx = x, ly = y;
    QColor c = colour(k);
    c.setAlpha(230);
    p.setPen(QPen(c, 1.5, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
    // In short pieces: Qt fills a translucent polyline as one path, which is slow when it crosses itself.
    for (qsizetype i = 0; i + 1 < line.size(); i += 16) p.drawPolyline(line.constData() + i, static_cast<int>(std::min<qsizetype>(17, line.size() - i)));
  }
  // Where each drone ended, over every path: a dot with a white rim, or a cross where it stopped.
  for (std::size_t k = 0; k < drones.size(); ++k) {
    const auto& [key, path] = *drones[k];
    if (const auto stop = t.stops.find(key); stop != t.stops.end()) {
      gui::draw_cross(p, f.at(stop->second.x, stop->second.y), colour(k));
      continue;
    }
    p.setPen(QPen(Qt::white, 1));
    p.setBrush(colour(k));
    if (!path.empty()) p.drawEllipse(f.at(path.back().first, path.back().second), 3.5, 3.5);
  }
  f.save(file);
}

// v in 0 … 100 along colours spaced evenly.
QColor ramp(const std::vector<QColor>& stops, double v) {
  const int last = static_cast<int>(stops.size()) - 1;
  const double at = std::clamp(v, 0.0, 100.0) / 100 * last;
  const int i = std::min(last - 1, static_cast<int>(at));
  const double w = at - i;
  const QColor &a = stops[static_cast<std::size_t>(i)], &b = stops[static_cast<std::size_t>(i + 1)];
  return QColor::fromRgbF(static_cast<float>(a.redF() + w * (b.redF() - a.redF())), static_cast<float>(a.greenF() + w * (b.greenF() - a.greenF())),
                          static_cast<float>(a.blueF() + w * (b.blueF() - a.blueF())));
}

// White (never visited) through yellow and orange to dark red (most visited).
QColor heat_colour(double v) {
  static const std::vector<QColor> stops = {QColor(255, 255, 255), QColor(255, 237, 160), QColor(254, 178, 76),
                                            QColor(240, 59, 32), QColor(128, 0, 38)};
  return ramp(stops, v);
}

// With groups, a cell takes the colour of the group there most, from a pale tint (a visited cell
// shows its hue) to the colour darkened (the busiest cell); white: never visited.
std::vector<QColor> group_ramp(std::size_t g) {
  const QColor c = group_colour(g);
  const QColor tint = QColor::fromRgbF(static_cast<float>(0.8 + 0.2 * c.redF()), static_cast<float>(0.8 + 0.2 * c.greenF()), static_cast<float>(0.8 + 0.2 * c.blueF()));
  return {tint, c, c.darker(190)};
}

constexpr int heat_columns = 60;

void heat_map(const TestData& t, const fs::path& file) {
  Points all;
  for (const auto& [id, path] : t.paths) all.insert(all.end(), path.begin(), path.end());
  const HeatGrid g = bin_positions(all, t.area, heat_columns);
  // With groups: each cell's positions per group, to find the group there most.
  const std::size_t groups = t.by_group() ? t.groups.size() : 1;
  std::vector<std::vector<double>> per_group(groups, std::vector<double>(g.values.size(), 0.0));
  if (groups > 1)
    for (const auto& [key, path] : t.paths)
      for (auto [x, y] : path)
        if (const int i = g.index_of(x, y); i >= 0 && y <= t.area.y1) ++per_group[key.first][static_cast<std::size_t>(i)];
  std::vector<std::vector<QColor>> ramps;
  for (std::size_t k = 0; k < groups; ++k) ramps.push_back(group_ramp(k));
  auto cell_colour = [&](std::size_t i) {
    if (groups == 1) return heat_colour(g.values[i]);
    if (g.values[i] == 0) return QColor(Qt::white);
    std::size_t most = 0;
    for (std::size_t k = 1; k < groups; ++k)
      if (per_group[k][i] > per_group[most][i]) most = k;
    return ramp(ramps[most], g.values[i]);
  };
  const int scale_width = 110 + 18 * static_cast<int>(groups - 1);  // a colour bar per group
  Figure f(QString::fromStdString(t.name) + ": where the drones were", plot_width, plot_height);
  f.x_axis("x (m)", t.view.x0, t.view.x1, true);
  f.y_axis("y (m)", t.view.y0, std::max(t.view.y1, t.area.y0 + g.rows * g.cell), true);
  f.equal_aspect();
  f.reserve_right(scale_width);
  if (groups > 1) {
    std::vector<LegendEntry> legend;
    for (std::size_t k = 0; k < groups; ++k) legend.push_back({LegendEntry::square, group_colour(k), QString::fromStdString(t.groups[k].name)});
    legend.push_back({LegendEntry::note, Qt::black, "(a cell: the group there most)"});
    f.legend(legend);
  }
  QPainter& p = f.begin();
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.columns; ++c) {
      const double x = t.area.x0 + c * g.cell, y = t.area.y0 + r * g.cell;
      p.fillRect(QRectF(f.at(x, y + g.cell), f.at(x + g.cell, y)).adjusted(0, 0, 0.6, 0.6), cell_colour(static_cast<std::size_t>(r * g.columns + c)));
    }
  MapShape outline = t.map;
  draw_map(f, outline);
  // Colour scale on the right: 0 … 100 % of the busiest cell (a bar per group, side by side).
  p.setClipping(false);
  const QRectF area = f.plot_area();
  const double bar_height = std::min(area.height() - 40, 500.0);
  QRectF bar;
  for (std::size_t k = 0; k < groups; ++k) {
    bar = groups == 1 ? QRectF(plot_width - 30 - 110 + 20, area.top() + 20, 26, bar_height)
                      : QRectF(plot_width - 30 - scale_width + 20 + 18 * static_cast<double>(k), area.top() + 20, 14, bar_height);
    for (int i = 0; i < static_cast<int>(bar.height()); ++i) {
      const double v = 100.0 * i / (bar.height() - 1);
      p.fillRect(QRectF(bar.left(), bar.bottom() - i - 1, bar.width(), 1), groups == 1 ? heat_colour(v) : ramp(ramps[k], v));
    }
    p.setPen(Qt::black);
    p.setBrush(Qt::NoBrush);
    p.drawRect(bar);
  }
  p.setFont(font(15));
  for (int v = 0; v <= 100; v += 20) {
    const double y = bar.bottom() - v / 100.0 * bar.height();
    p.drawLine(QPointF(bar.right(), y), QPointF(bar.right() + 5, y));
    p.drawText(QRectF(bar.right() + 8, y - 10, 50, 20), Qt::AlignLeft | Qt::AlignVCenter, QString::number(v));
  }
  p.save();
  p.translate(bar.right() + 60, bar.center().y());
  p.rotate(-90);
  p.drawText(QRectF(-200, -12, 400, 24), Qt::AlignCenter, "positions (% of busiest cell)");
  p.restore();
  f.save(file);
}

void speeds(const TestData& t, const fs::path& file) {
  std::vector<double> time, mean, lo, hi, sd_lo, sd_hi;
  // At most ~1000 points across 1000 pixels: consecutive times merged (mean of the means and sds, min, max).
  const std::size_t k = t.speeds.size() / 1000 + 1;
  std::vector<TestData::Speeds> merged;
  for (std::size_t i = 0; i < t.speeds.size(); i += k) {
    TestData::Speeds m{0, 0, 0, 1e300, -1e300};
    const std::size_t end = std::min(t.speeds.size(), i + k);
    for (std::size_t j = i; j < end; ++j) {
      const auto& s = t.speeds[j];
      m.time += s.time, m.mean += s.mean, m.sd += s.sd, m.min = std::min(m.min, s.min), m.max = std::max(m.max, s.max);
    }
    const double n = static_cast<double>(end - i);
    m.time /= n, m.mean /= n, m.sd /= n;
    merged.push_back(m);
  }
  for (const auto& s : merged)
    time.push_back(s.time), mean.push_back(s.mean), lo.push_back(s.min), hi.push_back(s.max),
        sd_lo.push_back(std::max(s.min, s.mean - s.sd)), sd_hi.push_back(std::min(s.max, s.mean + s.sd));
  Figure f(QString::fromStdString(t.name) + ": drone speeds", plot_width, plot_height);
  const auto [t0, t1] = range_of(time);
  f.x_axis("simulated time (s)", t0, t1);
  f.y_axis("speed (m/s)", 0, range_of(hi).second);
  QColor wide = palette(0), narrow = palette(0);
  wide.setAlpha(45), narrow.setAlpha(90);
  f.legend({{LegendEntry::line, palette(0), "mean"}, {LegendEntry::band, narrow, "mean ± 1 sd"}, {LegendEntry::band, wide, "min – max"}});
  f.begin();
  draw_band(f, time, lo, hi, wide);
  draw_band(f, time, sd_lo, sd_hi, narrow);
  draw_line(f, time, mean, palette(0).darker(130));
  f.save(file);
}

}  // namespace

void draw_test_plots(const fs::path& folder) {
  const TestData t = read_test(folder, true);
  // Drawn in a folder of their own, put in place as a whole: plots/ is always complete, and a run killed
  // while drawing leaves none, which --resume redraws (test_plots_missing).
  const fs::path dir = folder / ".plots.partial", done = folder / "plots";
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  if (ec) throw InputError(name_of(dir) + ": cannot create folder (" + ec.message() + ")");
  time_chart(t, per_group(t, t.found, &Group::found), "targets found", "targets found (%)", std::pair{0.0, 100.0}, dir / "found.png");
  auto any_value = [](const std::vector<double>& v) { return std::any_of(v.begin(), v.end(), [](double x) { return !std::isnan(x); }); };
  if (any_value(t.nn))
    time_chart(t, {{"", &t.nn, palette(0)}}, "distance to the nearest drone", "mean nearest-neighbour distance (m)", std::nullopt, dir / "nn_distance.png");
  if (t.has_coverage) time_chart(t, {{"", &t.coverage, palette(0)}}, "area covered", "coverage (%)", std::pair{0.0, 100.0}, dir / "coverage.png");
  // Counts and sums from 0, with room above the total's largest value (a flat line off the frame).
  auto from_zero = [](const std::vector<double>& total) { return std::pair{0.0, range_of(total).second * 1.04}; };
  if (any_value(t.alive)) time_chart(t, per_group(t, t.alive, &Group::alive), "drones alive", "drones flying", from_zero(t.alive), dir / "alive.png");
  if (std::any_of(t.energy.begin(), t.energy.end(), [](double x) { return x > 0; }))  // none used: no power model
    time_chart(t, per_group(t, t.energy, &Group::energy), "energy used", "energy used so far (Wh)", from_zero(t.energy), dir / "energy.png");
  if (!t.messages.empty()) {  // delivered and each kind of dropped, so far; sent (column 0) is their sum over receivers
    std::vector<Line> lines;
    double top = 0;
    const char* names[] = {"delivered", "out of range", "blocked by obstacles", "lost", "over the cap"};
    for (std::size_t k = 1; k < t.messages.size(); ++k) {
      lines.push_back({names[k - 1], &t.messages[k], palette(k - 1)});
      top = std::max(top, range_of(t.messages[k]).second);
    }
    time_chart(t, lines, "messages", "messages so far (message × receiver)", std::pair{0.0, std::max(top, 1.0) * 1.04}, dir / "messages.png");
  }
  if (!t.paths.empty()) {
    trajectories(t, dir / "trajectories.png");
    heat_map(t, dir / "heatmap.png");
    speeds(t, dir / "speeds.png");
  }
  fs::remove_all(done, ec);
  if (ec) throw InputError(name_of(done) + ": cannot remove the old plots (" + ec.message() + ")");
  fs::rename(dir, done, ec);
  if (ec) throw InputError(name_of(done) + ": cannot put the plots in place (" + ec.message() + ")");
  sync_folder(folder);
}

bool test_plots_missing(const fs::path& folder) {
  std::error_code ec;
  return !fs::is_directory(fs::symlink_status(folder / "plots", ec));
}

}  // namespace salsa::plots
