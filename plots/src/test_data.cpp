// One test folder's files read for its plots: the map's geometry, summary.csv, drones.csv and targets.csv.
#include "salsa/plots/results.hpp"

#include <algorithm>
#include <cmath>

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/files/map_file.hpp"
#include "strict_json.hpp"
#include "plot_helpers.hpp"
#include "test_data.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

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
  const MapData map = read_map_file(file);
  m.bounds = Rect{map.bounds.min.x, map.bounds.min.y, map.bounds.max.x, map.bounds.max.y};
  for (auto [from, into] : {std::pair{&map.obstacles, &m.solid}, std::pair{&map.hollow, &m.hollow}, std::pair{&map.lines, &m.lines}})
    for (const Polyline& line : *from) {
      QPolygonF poly;
      for (Vec2 p : line) poly << QPointF(p.x, p.y);
      into->push_back(poly);
    }
  return m;
}

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
  // Moving targets: a found one where it was found (where the drones' paths met it), a missed one where it ended.
  const auto c_found_x = in.find("found_x"), c_found_y = in.find("found_y");
  const bool moving = c_found_x && c_found_y;
  while (in.next()) {
    if (in[c_found].empty()) t.targets_missed.emplace_back(in.number(c_x), in.number(c_y));
    else if (moving) t.targets_found.emplace_back(in.number(*c_found_x), in.number(*c_found_y));
    else t.targets_found.emplace_back(in.number(c_x), in.number(c_y));
  }
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

}  // namespace

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

Rect test_area(const fs::path& folder) { return read_test(folder, true).area; }

}  // namespace salsa::plots
