#include "salsa/plots/results.hpp"

#include <QPainterPath>
#include <QPolygonF>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <tuple>
#include <charconv>
#include <cctype>

#include "figure.hpp"
#include "salsa/core/experiments/comparison.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "strict_json.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;
using nlohmann::json;
using Points = std::vector<std::pair<double, double>>;

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

std::string name_of(const fs::path& p) { return strict_json::printable(p.string(), 200); }

json read_json(const fs::path& file, const char* what) {
  try {
    return strict_json::read_file<json>(file, what);
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
}

// ---- The map: bounds and geometry from map.json (written by the runner) or the json map's file.
struct MapShape {
  std::optional<Rect> bounds;
  std::vector<QPolygonF> solid, hollow, lines;
};

MapShape read_map(const fs::path& folder, const json& config) {
  MapShape m;
  fs::path file = folder / "map.json";
  std::error_code ec;
  if (!fs::exists(file, ec)) {  // a folder written before map.json was: a map file still has the geometry
    if (!config.is_object() || !config.contains("map") || !config["map"].is_object() || !config["map"].contains("file") || !config["map"]["file"].is_string())
      return m;  // a generated map: its geometry is not in the folder
    file = config["map"]["file"].get<std::string>();
    if (!fs::exists(file, ec)) return m;
  }
  const json j = read_json(file, "a map file (see docs/maps.md)");
  const std::string name = name_of(file);
  auto point = [&](const json& p, const std::string& at) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw InputError(name + ": " + at + ": " + strict_json::shown(p) + " is not a point [x, y]");
    return QPointF(p[0].get<double>(), p[1].get<double>());
  };
  if (!j.is_object() || !j.contains("bounds") || !j["bounds"].is_object() || !j["bounds"].contains("min") || !j["bounds"].contains("max"))
    throw InputError(name + ": bounds: missing (a map file has {\"bounds\": {\"min\": [x, y], \"max\": [x, y]}})");
  const QPointF lo = point(j["bounds"]["min"], "bounds.min"), hi = point(j["bounds"]["max"], "bounds.max");
  if (!(hi.x() > lo.x() && hi.y() > lo.y()))
    throw InputError(name + ": bounds.max: " + strict_json::shown(j["bounds"]["max"]) + " must be greater than bounds.min " + strict_json::shown(j["bounds"]["min"]));
  m.bounds = Rect{lo.x(), lo.y(), hi.x(), hi.y()};
  for (auto [key, into] : {std::pair{"obstacles", &m.solid}, std::pair{"hollow", &m.hollow}, std::pair{"lines", &m.lines}}) {
    if (!j.contains(key)) continue;
    if (!j[key].is_array()) throw InputError(name + ": " + key + ": " + strict_json::shown(j[key]) + " is not a list of point lists");
    for (std::size_t i = 0; i < j[key].size(); ++i) {
      const json& shape = j[key][i];
      const std::string at = std::string(key) + "[" + std::to_string(i) + "]";
      if (!shape.is_array()) throw InputError(name + ": " + at + ": " + strict_json::shown(shape) + " is not a list of points");
      QPolygonF poly;
      for (std::size_t k = 0; k < shape.size(); ++k) poly << point(shape[k], at + "[" + std::to_string(k) + "]");
      into->push_back(poly);
    }
  }
  return m;
}

// ---- One test's files, each read once.
// A drone group (the fleet model): its name and its summary.csv columns, empty when absent.
struct Group {
  std::string name;
  std::vector<double> found, alive, energy;  // found: % of the targets
};

struct TestData {
  std::string name;
  MapShape map;
  Rect area;               // the map's bounds, else the extent of the data
  Rect view;               // what the map plots show: the area and a small margin
  double target_radius = 0;  // m, from config.json's target params (0: not given)
  std::vector<double> time, found, nn, coverage;  // summary.csv; nn: NaN when empty
  std::vector<double> alive, energy;              // summary.csv with the fleet model, else empty
  std::vector<std::vector<double>> messages;      // summary.csv's message counters (comm_columns) with "comm", else empty
  bool has_coverage = false;
  std::vector<Group> groups;  // in group order: summary.csv's, then any other drones.csv names
  bool drone_groups = false;  // drones.csv has the group column
  // drones.csv, by group (its index in `groups`, 0 without the column) and drone id.
  using DroneKey = std::pair<std::size_t, long>;
  std::map<DroneKey, Points> paths;
  struct Stop { double x, y; bool failed; };  // the first row a drone is landed or failed
  std::map<DroneKey, Stop> stops;
  struct Speeds { double time, mean, sd, min, max; };
  std::vector<Speeds> speeds;
  Points targets_found, targets_missed;            // targets.csv
  bool by_group() const { return drone_groups && groups.size() > 1; }
};

void read_summary(TestData& t, const fs::path& file) {
  CsvReader in(file);
  const std::size_t c_time = in.column("time"), c_found = in.column("fraction_found");
  const auto c_nn = in.find("mean_nn_distance"), c_coverage = in.find("coverage"), c_alive = in.find("alive"),
             c_energy = in.find("energy_used_Wh"), c_count = in.find("targets_found");
  t.has_coverage = c_coverage.has_value();
  struct Columns { std::optional<std::size_t> found, alive, energy; };
  std::vector<Columns> group_columns;
  for (const std::string& h : in.header())
    if (h.size() > 6 && h.ends_with(".found")) {
      const std::string name = h.substr(0, h.size() - 6);
      t.groups.push_back({name, {}, {}, {}});
      group_columns.push_back({in.find(h), in.find(name + ".alive"), in.find(name + ".energy_used_Wh")});
    }
  std::vector<std::size_t> message_columns;
  for (const char* name : comm_columns)
    if (const auto c = in.find(name)) message_columns.push_back(*c);
  if (message_columns.size() != std::size(comm_columns)) message_columns.clear();  // all or none
  t.messages.assign(message_columns.size(), {});
  const double nan = std::nan("");
  double targets = 0;  // a group's found is a count: the test's targets = targets_found / fraction_found
  while (in.next()) {
    t.time.push_back(in.number(c_time));
    const double fraction = in.number(c_found);
    t.found.push_back(fraction * 100);
    if (c_count && fraction > 0) targets = in.number(*c_count) / fraction;
    t.nn.push_back(c_nn ? in.optional_number(*c_nn).value_or(nan) : nan);
    if (c_coverage) t.coverage.push_back(in.optional_number(*c_coverage).value_or(nan) * 100);
    if (c_alive) t.alive.push_back(in.optional_number(*c_alive).value_or(nan));
    if (c_energy) t.energy.push_back(in.optional_number(*c_energy).value_or(nan));
    for (std::size_t k = 0; k < message_columns.size(); ++k) t.messages[k].push_back(in.optional_number(message_columns[k]).value_or(nan));
    for (std::size_t g = 0; g < group_columns.size(); ++g) {
      const Columns& c = group_columns[g];
      for (auto [column, into] : {std::pair{c.found, &t.groups[g].found}, std::pair{c.alive, &t.groups[g].alive}, std::pair{c.energy, &t.groups[g].energy}})
        if (column) into->push_back(in.optional_number(*column).value_or(nan));
    }
  }
  for (Group& g : t.groups)
    for (double& v : g.found) v = targets > 0 ? v / targets * 100 : 0;  // nothing found yet: every count is 0
}

// drones.csv is written time by time: speeds are summed per time as the rows stream past (of the
// drones flying: a landed or failed drone stands still).
void read_drones(TestData& t, const fs::path& file) {
  CsvReader in(file);
  const std::size_t c_time = in.column("time"), c_id = in.column("id"), c_x = in.column("x"), c_y = in.column("y"),
                    c_vx = in.column("vx"), c_vy = in.column("vy");
  const auto c_group = in.find("group"), c_status = in.find("status");
  t.drone_groups = c_group.has_value();
  std::size_t group = 0;  // the last row's, looked up again only when the name changes
  std::string group_name;
  double now = std::nan(""), n = 0, sum = 0, sum2 = 0, lo = 0, hi = 0;
  auto flush = [&] {
    if (n == 0) return;
    const double mean = sum / n;
    t.speeds.push_back({now, mean, n > 1 ? std::sqrt(std::max(0.0, (sum2 - n * mean * mean) / (n - 1))) : 0.0, lo, hi});
  };
  while (in.next()) {
    const double time = in.number(c_time);
    if (time != now) {
      flush();
      now = time, n = sum = sum2 = 0, lo = 1e300, hi = -1e300;
    }
    if (c_group && in[*c_group] != group_name) {
      group_name = in[*c_group];
      const auto known = std::find_if(t.groups.begin(), t.groups.end(), [&](const Group& g) { return g.name == group_name; });
      group = static_cast<std::size_t>(known - t.groups.begin());
      if (known == t.groups.end()) t.groups.push_back({group_name, {}, {}, {}});
    }
    const TestData::DroneKey key{group, static_cast<long>(in.number(c_id))};
    const double x = in.number(c_x), y = in.number(c_y);
    // A stopped drone's path ends where it stopped: its rows after that would only pile up in one
    // cell of the heat map.
    const std::string_view status = c_status ? in[*c_status] : std::string_view();
    if (status == "landed" || status == "failed") {
      if (t.stops.try_emplace(key, TestData::Stop{x, y, status == "failed"}).second) t.paths[key].emplace_back(x, y);
      continue;
    }
    t.paths[key].emplace_back(x, y);
    const double speed = std::hypot(in.number(c_vx), in.number(c_vy));
    ++n, sum += speed, sum2 += speed * speed, lo = std::min(lo, speed), hi = std::max(hi, speed);
  }
  flush();
}

void read_targets(TestData& t, const fs::path& file) {
  CsvReader in(file);
  const std::size_t c_x = in.column("x"), c_y = in.column("y"), c_found = in.column("found_time");
  while (in.next()) (in[c_found].empty() ? t.targets_missed : t.targets_found).emplace_back(in.number(c_x), in.number(c_y));
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

Rect data_extent(const TestData& t) {
  Rect r{1e300, 1e300, -1e300, -1e300};
  auto add = [&](const Points& ps) {
    for (auto [x, y] : ps) r.x0 = std::min(r.x0, x), r.y0 = std::min(r.y0, y), r.x1 = std::max(r.x1, x), r.y1 = std::max(r.y1, y);
  };
  for (const auto& [id, path] : t.paths) add(path);
  add(t.targets_found), add(t.targets_missed);
  if (r.x0 > r.x1) return Rect{};
  const double pad = 0.02 * std::max({r.x1 - r.x0, r.y1 - r.y0, 1.0});
  return Rect{r.x0 - pad, r.y0 - pad, r.x1 + pad, r.y1 + pad};
}

TestData read_test(const fs::path& folder, bool with_drones) {
  TestData t;
  t.name = folder.filename().string();
  if (t.name.empty()) t.name = folder.parent_path().filename().string();
  if (!is_file(folder / "config.json"))
    throw InputError(name_of(folder) + ": no config.json (allowed: a test folder written by 'salsa run')");
  const json config = read_json(folder / "config.json", "a resolved test (config.json)");
  t.map = read_map(folder, config);
  if (config.is_object() && config.contains("targets") && config["targets"].is_object() && config["targets"].contains("params") &&
      config["targets"]["params"].is_object() && config["targets"]["params"].contains("radius") &&
      config["targets"]["params"]["radius"].is_number())
    t.target_radius = std::max(0.0, config["targets"]["params"]["radius"].get<double>());
  read_summary(t, folder / "summary.csv");
  if (with_drones && is_file(folder / "drones.csv")) read_drones(t, folder / "drones.csv");
  if (is_file(folder / "targets.csv")) read_targets(t, folder / "targets.csv");
  t.area = t.map.bounds ? *t.map.bounds : data_extent(t);  // data_extent has its margin already
  t.view = t.area;
  if (t.map.bounds) {  // the bounds' walls just inside the frame
    const double margin = 0.015 * std::max(t.area.x1 - t.area.x0, t.area.y1 - t.area.y0);
    t.view = Rect{t.area.x0 - margin, t.area.y0 - margin, t.area.x1 + margin, t.area.y1 + margin};
  }
  return t;
}

// ---- Drawing helpers.
void draw_line(Figure& f, const std::vector<double>& x, const std::vector<double>& y, const QColor& colour, double width = 2.5,
               Qt::PenStyle style = Qt::SolidLine) {
  QPainterPath path;
  bool pen_down = false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::isnan(y[i])) {
      pen_down = false;
      continue;
    }
    pen_down ? path.lineTo(f.at(x[i], y[i])) : path.moveTo(f.at(x[i], y[i]));
    pen_down = true;
  }
  f.painter().setBrush(Qt::NoBrush);
  f.painter().setPen(QPen(colour, width, style, Qt::RoundCap, Qt::RoundJoin));
  f.painter().drawPath(path);
}

void draw_band(Figure& f, const std::vector<double>& x, const std::vector<double>& lo, const std::vector<double>& hi, QColor colour) {
  QPolygonF band;
  for (std::size_t i = 0; i < x.size(); ++i) band << f.at(x[i], lo[i]);
  for (std::size_t i = x.size(); i-- > 0;) band << f.at(x[i], hi[i]);
  f.painter().setPen(Qt::NoPen);
  f.painter().setBrush(colour);
  f.painter().drawPolygon(band);
}

std::pair<double, double> range_of(const std::vector<double>& v) {
  double lo = 1e300, hi = -1e300;
  for (double x : v)
    if (!std::isnan(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  return lo > hi ? std::pair{0.0, 1.0} : std::pair{lo, hi};
}

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
      draw_cross(p, f.at(stop->second.x, stop->second.y), colour(k));
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

Rect test_area(const fs::path& folder) { return read_test(folder, true).area; }

void draw_test_plots(const fs::path& folder) {
  const TestData t = read_test(folder, true);
  const fs::path dir = folder / "plots";
  std::error_code ec;
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
}

// ---- Queue plots.

bool natural_less(std::string_view a, std::string_view b) {
  auto number_at = [](std::string_view s, std::size_t i) {  // a number starts at a digit, or a '-' before one after a non-letter
    return i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) ||
                            (s[i] == '-' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])) &&
                             (i == 0 || !std::isalnum(static_cast<unsigned char>(s[i - 1])))));
  };
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (number_at(a, i) && number_at(b, j)) {
      double x = 0, y = 0;
      const char* ea = std::from_chars(a.data() + i, a.data() + a.size(), x).ptr;
      const char* eb = std::from_chars(b.data() + j, b.data() + b.size(), y).ptr;
      if (x != y) return x < y;
      if (ea > a.data() + i && eb > b.data() + j) {
        i = static_cast<std::size_t>(ea - a.data()), j = static_cast<std::size_t>(eb - b.data());
        continue;
      }
    }
    if (a[i] != b[j]) return a[i] < b[j];
    ++i, ++j;
  }
  return a.size() - i < b.size() - j;
}

namespace {

struct QueueRow {
  std::string name, variant, drones, behavior, condition, condition_label;
  double size, found;  // drones as a number; found: %
  std::map<std::string, double> params;  // the behavior's parameters: summary.csv's behavior.<p>
};

std::vector<std::string> in_order(const std::vector<QueueRow>& rows, std::string QueueRow::*key) {
  std::vector<std::string> out;
  for (const auto& r : rows)
    if (std::find(out.begin(), out.end(), r.*key) == out.end()) out.push_back(r.*key);
  return out;
}

std::vector<std::string> sizes_of(const std::vector<QueueRow>& rows) {
  std::map<double, std::string> by_size;
  for (const auto& r : rows) by_size.emplace(r.size, r.drones);
  std::vector<std::string> sizes;
  for (const auto& [n, text] : by_size) sizes.push_back(text);
  return sizes;
}

/// Variants as the plots show them: behaviors in order of first appearance, each one's defaults first,
/// then its other variants with numbers compared as numbers (alpha = 1 < 1.4 < 1.8 < 10).
std::vector<std::string> variants_of(const std::vector<QueueRow>& rows) {
  const auto behaviors = in_order(rows, &QueueRow::behavior);
  std::map<std::string, std::size_t> place;  // variant → its behavior's place
  for (const auto& r : rows)
    place.emplace(r.variant, static_cast<std::size_t>(std::find(behaviors.begin(), behaviors.end(), r.behavior) - behaviors.begin()));
  std::vector<std::string> out = in_order(rows, &QueueRow::variant);
  std::stable_sort(out.begin(), out.end(), [&](const std::string& a, const std::string& b) {
    if (place[a] != place[b]) return place[a] < place[b];
    const bool da = a.ends_with(" (defaults)"), db = b.ends_with(" (defaults)");
    if (da != db) return da;
    return natural_less(a, b);
  });
  return out;
}

/// The conditions in order of first appearance ("" for a queue without conditions).
std::vector<std::string> conditions_of(const std::vector<QueueRow>& rows) { return in_order(rows, &QueueRow::condition); }

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

/// Legend entries naming each condition by what it changes (none without conditions).
void condition_notes(const std::vector<QueueRow>& rows, std::vector<LegendEntry>& legend, bool with_lines) {
  const auto conditions = conditions_of(rows);
  if (conditions.size() < 2 && conditions.front().empty()) return;
  for (std::size_t c = 0; c < conditions.size(); ++c)
    legend.push_back({with_lines ? LegendEntry::line : LegendEntry::note, QColor(90, 90, 90), condition_text(rows, conditions[c]), condition_style(c)});
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
        const double n = static_cast<double>(values.size());
        const double mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
        double ss = 0;
        for (double x : values) ss += (x - mean) * (x - mean);
        const double half = values.size() > 1 ? t_half_width(values.size(), std::sqrt(ss / (n - 1))) : 0;
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

// One row of an interval plot: a label on the left, the mean as a square with its 95 % interval, a note
// on the right; under a heading (what the rows share: condition, swarm size).
struct IntervalRow {
  QString heading, label, note;
  std::optional<double> mean, lo, hi;
};

// Rows of estimates with their 95 % intervals against a dashed line at 0 (comparison.png, did.png),
// grouped under their headings in order of first appearance.
void interval_plot(const std::vector<IntervalRow>& given, const QString& title, const QString& x_label, const fs::path& file) {
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
  f.save(file);
}

QString text_of(std::string_view v) { return QString::fromUtf8(v.data(), static_cast<qsizetype>(v.size())); }

/// "dropout (drones → 14 at 200 s)"; a queue without conditions: "".
using ConditionLabels = std::map<std::string, std::string>;
QString condition_words(const ConditionLabels& labels, const std::string& condition) {
  const auto it = labels.find(condition);
  return QString::fromStdString(condition + (it == labels.end() || it->second.empty() ? "" : " (" + it->second + ")"));
}
QString metric_words(const std::string& metric) { return QString::fromStdString(metric == "fraction_found" ? "targets found" : metric); }

// comparison.png: one row per pair of variants in a cell and condition.
void forest(const fs::path& csv, const fs::path& file, const ConditionLabels& labels) {
  CsvReader in(csv);
  const std::size_t c_a = in.column("variant_a"), c_b = in.column("variant_b"), c_n = in.column("n"), c_mean = in.column("mean_diff"),
                    c_lo = in.column("ci_low"), c_hi = in.column("ci_high"), c_win = in.column("win_rate_a"),
                    c_drones = in.column("drones"), c_metric = in.column("metric");
  const auto c_condition = in.find("condition");
  std::vector<IntervalRow> rows;
  std::string metric;
  while (in.next()) {
    metric = std::string(in[c_metric]);
    const double scale = metric.starts_with("fraction") ? 100 : 1;
    auto scaled = [&](std::size_t c) { auto v = in.optional_number(c); return v ? std::optional(*v * scale) : v; };
    const auto win = in.optional_number(c_win);
    const std::string condition(c_condition ? in[*c_condition] : std::string_view{});
    rows.push_back({(condition.empty() ? "" : condition_words(labels, condition) + ", ") + text_of(in[c_drones]) + " drones",
                    text_of(in[c_a]) + " − " + text_of(in[c_b]), "n = " + text_of(in[c_n]) + (win ? ", A higher in " + QString::number(*win * 100, 'f', 0) + " %" : QString()),
                    scaled(c_mean), scaled(c_lo), scaled(c_hi)});
  }
  const bool percent = metric.starts_with("fraction");
  interval_plot(rows, "Paired differences A − B in " + metric_words(metric) + " (mean, 95 % CI)",
                percent ? "difference A − B (percentage points)" : "difference A − B (" + QString::fromStdString(metric) + ")", file);
}

// did.png: one row per pair of variants and condition: (A − B | condition) − (A − B | baseline).
void did_plot(const fs::path& csv, const fs::path& file, const ConditionLabels& labels) {
  CsvReader in(csv);
  const std::size_t c_a = in.column("variant_a"), c_b = in.column("variant_b"), c_base = in.column("baseline"), c_cond = in.column("condition"),
                    c_n = in.column("n"), c_did = in.column("did"), c_lo = in.column("ci_low"), c_hi = in.column("ci_high"),
                    c_drones = in.column("drones"), c_metric = in.column("metric");
  std::vector<IntervalRow> rows;
  std::string metric;
  while (in.next()) {
    metric = std::string(in[c_metric]);
    const double scale = metric.starts_with("fraction") ? 100 : 1;
    auto scaled = [&](std::size_t c) { auto v = in.optional_number(c); return v ? std::optional(*v * scale) : v; };
    rows.push_back({condition_words(labels, std::string(in[c_cond])) + " against " + text_of(in[c_base]) + ", " + text_of(in[c_drones]) + " drones",
                    text_of(in[c_a]) + " − " + text_of(in[c_b]), "n = " + text_of(in[c_n]) + " repeats", scaled(c_did), scaled(c_lo), scaled(c_hi)});
  }
  const bool percent = metric.starts_with("fraction");
  interval_plot(rows, "How a condition changes A − B in " + metric_words(metric) + " (mean, 95 % CI)",
                percent ? "change of A − B (percentage points)" : "change of A − B (" + QString::fromStdString(metric) + ")", file);
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
      const double span = *xs.rbegin() - *xs.begin();
      f.x_axis(QString::fromStdString(behavior + "." + param), *xs.begin() - 0.03 * span, *xs.rbegin() + 0.03 * span);
      double lo = 100, hi = 0;
      struct Point { double x, mean, lo, hi; };
      std::vector<std::vector<Point>> drawn;
      for (const std::string& key : order) {
        std::vector<Point>& points = drawn.emplace_back();
        for (const auto& [x, found] : lines[key]) {
          const double n = static_cast<double>(found.size());
          const double mean = std::accumulate(found.begin(), found.end(), 0.0) / n;
          double ss = 0;
          for (double v : found) ss += (v - mean) * (v - mean);
          const double half = found.size() > 1 ? t_half_width(found.size(), std::sqrt(ss / (n - 1))) : 0;
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

/// A setting that differs between tests of one variant, swarm size, condition and repeat is one the
/// queue varies besides them (a sweep.set key: "failures.drone_mtbf"). Each of its values becomes part
/// of the row's condition ("failures.drone_mtbf = 3000"), so the plots keep its values apart.
void split_by_swept_settings(std::vector<QueueRow>& rows, const std::vector<std::vector<std::string>>& settings,
                             const std::vector<std::string>& header, const std::vector<std::size_t>& columns) {
  std::map<std::tuple<std::string, std::string, std::string, std::string>, std::size_t> first;  // the group's first row
  std::vector<bool> swept(columns.size(), false);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto [it, fresh] = first.try_emplace({rows[i].variant, rows[i].drones, rows[i].condition, settings[i].back()}, i);
    if (!fresh)
      for (std::size_t k = 0; k < columns.size(); ++k) swept[k] = swept[k] || settings[i][k] != settings[it->second][k];
  }
  // A setting that follows another swept one value for value says nothing more (failures.camera_mtbf
  // written as 0 exactly where failures.drone_mtbf is set): the first of them names the split.
  for (std::size_t k = 0; k < columns.size(); ++k)
    for (std::size_t j = 0; j < k && swept[k]; ++j) {
      if (!swept[j]) continue;
      std::map<std::string, std::string> k_of_j, j_of_k;
      bool same = true;
      for (std::size_t i = 0; i < rows.size() && same; ++i)
        same = k_of_j.try_emplace(settings[i][j], settings[i][k]).first->second == settings[i][k] &&
               j_of_k.try_emplace(settings[i][k], settings[i][j]).first->second == settings[i][j];
      if (same) swept[k] = false;
    }
  auto shown = [](const std::string& v) {
    if (v.empty()) return std::string("none");
    double x = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    return ec == std::errc() && end == v.data() + v.size() ? Parameter::format(x) : v;  // "3000.0" as 3000
  };
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (swept[k]) rows[i].condition += (rows[i].condition.empty() ? "" : ", ") + header[columns[k]] + " = " + shown(settings[i][k]);
}

}  // namespace

void start_plotting() { ensure_application(); }

namespace {

/// OUT/summary.csv's ok tests as the plots group them, and their conditions' labels as comparison.csv
/// and did.csv name the conditions.
std::vector<QueueRow> read_queue_rows(const fs::path& out, ConditionLabels* labels) {
  CsvReader in(out / "summary.csv");
  const std::size_t c_name = in.column("name"), c_status = in.column("status"), c_variant = in.column("variant"),
                    c_drones = in.column("drones");
  const auto c_found = in.find("fraction_found");  // absent when every test failed: nothing to draw then
  const auto c_behavior = in.find("behavior"), c_condition = in.find("condition"), c_label = in.find("condition_label");
  std::vector<std::pair<std::string, std::size_t>> c_params;  // the single form's behavior.<p>
  for (std::size_t c = 0; c < in.header().size(); ++c)
    if (in.header()[c].starts_with("behavior.")) c_params.emplace_back(in.header()[c].substr(9), c);
  auto text = [&](std::optional<std::size_t> c) { return c ? std::string(in[*c]) : std::string(); };
  // The settings a test was made with (the columns before the outcome's) other than those the plots
  // already group by: one the queue varies (a sweep.set key) splits the groups too, not pooled.
  std::vector<std::size_t> c_settings;
  const auto c_repeat = in.find("repeat");
  for (std::size_t c = 0; c < in.header().size() && !in.header()[c].starts_with("outcome."); ++c) {
    const std::string& h = in.header()[c];
    static const std::set<std::string> grouped{"name", "status", "error", "cell", "variant", "condition", "condition_label",
                                               "behavior", "repeat", "seed", "drones"};
    if (!grouped.contains(h) && !h.starts_with("behavior.") && !h.starts_with("versions.")) c_settings.push_back(c);
  }
  std::vector<QueueRow> rows;
  std::vector<std::vector<std::string>> settings;  // per row, c_settings' values
  while (in.next())
    if (in[c_status] == "ok") {
      QueueRow r{std::string(in[c_name]), std::string(in[c_variant]), std::string(in[c_drones]), text(c_behavior), text(c_condition),
                 text(c_label), in.number(c_drones), in.number(c_found ? *c_found : in.column("fraction_found")) * 100, {}};
      for (const auto& [p, c] : c_params)
        if (const auto v = in.optional_number(c)) r.params[p] = *v;
      settings.emplace_back();
      for (const std::size_t c : c_settings) settings.back().emplace_back(in[c]);
      settings.back().emplace_back(text(c_repeat));  // last: the repeat, to find tests that differ in a setting alone
      rows.push_back(std::move(r));
    }
  if (labels)
    for (const auto& r : rows) labels->emplace(r.condition, r.condition_label);
  split_by_swept_settings(rows, settings, in.header(), c_settings);
  return rows;
}

}  // namespace

std::vector<std::string> plotted_conditions(const fs::path& out) {
  std::vector<std::string> out_conditions;
  for (const QueueRow& r : read_queue_rows(out, nullptr)) out_conditions.push_back(r.condition);
  return out_conditions;
}

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
  if (is_file(out / "comparison.csv")) forest(out / "comparison.csv", dir / "comparison.png", labels);
  if (is_file(out / "did.csv")) did_plot(out / "did.csv", dir / "did.png", labels);
  score_plots(rows, dir);
}

}  // namespace salsa::plots
