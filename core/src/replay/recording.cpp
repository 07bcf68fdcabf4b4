// A finished test folder read back: config.json (the groups), map.json, targets.csv, and the drones'
// states from the archive or, without one, from drones.csv.
#include "salsa/core/replay/recording.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/files/input_error.hpp"
#include "salsa/core/files/map_file.hpp"
#include "salsa/core/replay/archive.hpp"
#include "strict_json.hpp"

namespace salsa {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

std::string shown(const fs::path& p) { return strict_json::printable(p.string(), 200); }

/// The folder holds a finished test: its manifest (written last but config.json) and config.json.
/// A file the recording reads must have the size the manifest gives it (a cut copy is refused).
json finished_test(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw InputError(shown(folder) + ": not a folder (a finished test's folder, as salsa run wrote it)");
  for (const char* file : {"manifest.json", "config.json", "map.json", "targets.csv"})
    if (!fs::is_regular_file(folder / file, ec))
      throw InputError(shown(folder) + ": not a finished test (no " + file + "; a test folder that salsa run finished holds it)");
  try {
    return strict_json::read_file<json>(folder / "manifest.json", "a test's manifest.json");
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
}

void check_size(const json& manifest, const fs::path& file) {
  const std::string name = file.filename().string();
  if (!manifest.is_object() || !manifest.contains("files") || !manifest["files"].is_object() || !manifest["files"].contains(name)) return;
  const json& want = manifest["files"][name];
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (want.is_number_unsigned() && !ec && size != want.get<std::uintmax_t>())
    throw InputError(shown(file) + ": " + std::to_string(size) + " bytes where the test's manifest.json says " +
                     std::to_string(want.get<std::uintmax_t>()) + " (a cut or changed copy)");
}

json read_config(const fs::path& file) {
  try {
    return strict_json::read_file<json>(file, "a test's config.json");
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
}

double number_or(const json& j, const char* key, double fallback) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

/// The groups as config.json gives them (the single form is one group, "swarm"); with their drone
/// counts, which give the ids' groups when drones.csv has no group column.
std::vector<RecordedGroup> read_groups(const json& config, Vec2 map_spawn, std::vector<std::size_t>& counts) {
  std::vector<RecordedGroup> groups;
  auto add = [&](const json& g, std::string name) {
    RecordedGroup r;
    r.name = std::move(name);
    const json drone = g.contains("drone") ? g["drone"] : json::object();
    r.radius = number_or(drone, "radius", 1);
    r.camera_range = number_or(drone, "camera_range", 0);
    r.detection_range = number_or(drone, "detection_range", 0);
    r.obstacle_range = number_or(drone, "obstacle_range", 0);
    r.base = {nan, nan};  // the map's spawn: known only when the first group has it too (map.json's spawn is the first group's base)
    if (g.contains("spawn") && g["spawn"].is_object() && g["spawn"].contains("point")) {
      const json& p = g["spawn"]["point"];
      if (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number()) r.base = {p[0].get<double>(), p[1].get<double>()};
    }
    if (groups.empty() && std::isnan(r.base.x)) r.base = map_spawn;
    counts.push_back(static_cast<std::size_t>(std::max(0.0, number_or(g, "drones", 0))));
    groups.push_back(std::move(r));
  };
  if (config.contains("groups") && config["groups"].is_array())
    for (const json& g : config["groups"]) add(g, g.contains("name") && g["name"].is_string() ? g["name"].get<std::string>() : "group");
  else
    add(config, "swarm");
  return groups;
}

void read_targets(Recording& r, const fs::path& file) {
  CsvReader in(file);
  const std::size_t c_x = in.column("x"), c_y = in.column("y"), c_time = in.column("found_time"), c_by = in.column("found_by");
  while (in.next()) {
    r.targets.push_back({in.number(c_x), in.number(c_y)});
    r.found_time.push_back(in.optional_number(c_time).value_or(nan));
    r.found_by.push_back(static_cast<std::int64_t>(in.optional_number(c_by).value_or(-1)));
  }
}

RecordedColumn declared(std::string_view name) {
  for (const StateColumn& c : declared_drone_columns())
    if (c.name == name) return {std::string(c.name), std::string(c.unit), std::string(c.model), std::string(c.meaning), c.type, c.width, {}};
  return {std::string(name), "", "", "", StateColumn::Type::f64, 1, {}};
}

/// drones.csv: one row per logged time and drone not removed. Its fleet columns become the state
/// columns they were written from (status text → status, camera_works and errand; Wh → J).
void read_drones_csv(Recording& r, const fs::path& file, const std::vector<std::size_t>& counts) {
  CsvReader in(file);
  const std::size_t c_time = in.column("time"), c_id = in.column("id");
  const std::size_t c_x = in.column("x"), c_y = in.column("y"), c_vx = in.column("vx"), c_vy = in.column("vy");
  const std::optional<std::size_t> c_group = in.find("group"), c_status = in.find("status"), c_energy = in.find("energy_used_Wh"),
                                   c_charging = in.find("charging_s");
  // The state columns written by name after these (--drone-columns): NAME, or NAME_x and NAME_y.
  struct Extra {
    RecordedColumn column;
    std::vector<std::size_t> fields;
  };
  std::vector<Extra> extras;
  for (const StateColumn& c : declared_drone_columns()) {
    if (c.name == "position" || c.name == "velocity" || c.name == "group" || c.name == "status") continue;  // the usual columns
    Extra e{declared(c.name), {}};
    if (c.width == 1) {
      if (auto at = in.find(c.name)) e.fields.push_back(*at);
    } else if (auto x = in.find(std::string(c.name) + "_x"), y = in.find(std::string(c.name) + "_y"); x && y) {
      e.fields = {*x, *y};
    }
    if (!e.fields.empty()) extras.push_back(std::move(e));
  }
  std::map<std::string, std::uint32_t> group_index;
  for (std::size_t g = 0; g < r.groups.size(); ++g) group_index[r.groups[g].name] = static_cast<std::uint32_t>(g);

  // Rows in the file's order: each logged time's drones, ascending ids.
  struct Row {
    std::size_t frame, id;
  };
  std::vector<Row> rows;
  std::vector<double> values;  // per row: x, y, vx, vy, group, status, camera, energy, errand, charging, extras…
  std::size_t extra_width = 0;
  for (const Extra& e : extras) extra_width += e.fields.size();
  const std::size_t stride = 10 + extra_width;
  std::size_t drones = 0;
  for (std::size_t n : counts) drones += n;
  while (in.next()) {
    const double t = in.number(c_time);
    if (r.times.empty() || t > r.times.back()) r.times.push_back(t);
    else if (t < r.times.back())
      throw InputError(shown(file) + ": line " + std::to_string(in.line()) + ": time " + std::string(in[c_time]) + " goes back (rows are in time order)");
    const double id = in.number(c_id);
    if (id < 0 || id != std::floor(id) || id > 1e8)
      throw InputError(shown(file) + ": line " + std::to_string(in.line()) + ": id " + std::string(in[c_id]) + " is not a drone id (0 … 10^8)");
    rows.push_back({r.times.size() - 1, static_cast<std::size_t>(id)});
    drones = std::max(drones, rows.back().id + 1);
    values.insert(values.end(), {in.number(c_x), in.number(c_y), in.number(c_vx), in.number(c_vy)});
    double group = nan, status = 0, camera = 1, energy = nan, errand = 0, charging = nan;
    if (c_group) {
      const auto it = group_index.find(std::string(in[*c_group]));
      if (it == group_index.end())
        throw InputError(shown(file) + ": line " + std::to_string(in.line()) + ": group '" + std::string(in[*c_group]) + "' is not one of config.json's groups");
      group = it->second;
    }
    if (c_status) {
      const std::string_view s = in[*c_status];
      if (s == "landed") status = 1;
      else if (s == "failed") status = 2;
      else if (s == "camera_failed") camera = 0;
      else if (s == "returning") errand = 1;
      else if (s == "charging") errand = 2;
      else if (s == "outbound") errand = 3;
      else if (s != "flying")
        throw InputError(shown(file) + ": line " + std::to_string(in.line()) + ": status '" + std::string(s) +
                         "' (allowed: flying, camera_failed, returning, charging, outbound, landed, failed)");
    }
    if (c_energy) energy = in.number(*c_energy) * 3600;
    if (c_charging) charging = in.number(*c_charging);
    values.insert(values.end(), {group, status, camera, energy, errand, charging});
    for (const Extra& e : extras)
      for (std::size_t f : e.fields) values.push_back(in.optional_number(f).value_or(nan));
  }
  if (r.times.empty()) throw InputError(shown(file) + ": no rows (a finished test logs time 0 at least)");
  r.drones = drones;

  // The ids' groups when drones.csv does not name them: ids run over the groups in order.
  std::vector<double> group_of(drones, 0);
  for (std::size_t g = 0, id = 0; g < counts.size(); ++g)
    for (std::size_t k = 0; k < counts[g] && id < drones; ++k) group_of[id++] = static_cast<double>(g);

  const std::size_t frames = r.times.size(), cells = frames * drones;
  auto column = [&](std::string_view name, double fill) {
    RecordedColumn c = declared(name);
    c.values.assign(cells * c.width, fill);
    return c;
  };
  RecordedColumn position = column("position", nan), velocity = column("velocity", nan), group = column("group", nan), status = column("status", 3);
  RecordedColumn camera = column("camera_works", nan), energy = column("energy_used", nan), errand = column("errand", nan), charging = column("charging_time", nan);
  for (std::size_t f = 0; f < frames; ++f)
    for (std::size_t id = 0; id < drones; ++id) group.values[f * drones + id] = group_of[id];
  std::vector<RecordedColumn> extra_columns;
  for (const Extra& e : extras) {
    extra_columns.push_back(e.column);
    extra_columns.back().values.assign(cells * e.column.width, nan);
  }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t at = rows[k].frame * drones + rows[k].id;
    const double* v = &values[k * stride];
    position.values[2 * at] = v[0], position.values[2 * at + 1] = v[1];
    velocity.values[2 * at] = v[2], velocity.values[2 * at + 1] = v[3];
    if (c_group) group.values[at] = v[4];
    status.values[at] = v[5];
    camera.values[at] = v[6];
    energy.values[at] = v[7];
    errand.values[at] = v[8];
    charging.values[at] = v[9];
    std::size_t f = 10;
    for (RecordedColumn& c : extra_columns)
      for (std::size_t w = 0; w < c.width; ++w) c.values[at * c.width + w] = v[f++];
  }
  r.columns.push_back(std::move(position));
  r.columns.push_back(std::move(velocity));
  r.columns.push_back(std::move(group));
  r.columns.push_back(std::move(status));
  if (c_status) r.columns.push_back(std::move(camera));
  if (c_energy) r.columns.push_back(std::move(energy));
  if (c_status) r.columns.push_back(std::move(errand));
  if (c_charging) r.columns.push_back(std::move(charging));
  for (RecordedColumn& c : extra_columns)
    if (!r.column(c.name)) r.columns.push_back(std::move(c));
}

}  // namespace

const RecordedColumn* Recording::column(std::string_view name) const {
  for (const RecordedColumn& c : columns)
    if (c.name == name) return &c;
  return nullptr;
}

std::size_t Recording::frame_at(double t) const {
  const auto it = std::upper_bound(times.begin(), times.end(), t);
  return it == times.begin() ? 0 : static_cast<std::size_t>(it - times.begin()) - 1;
}

Vec2 Recording::position(std::size_t frame, std::size_t id) const {
  const RecordedColumn& c = columns.front();  // position is always first
  return {at(c, frame, id, 0), at(c, frame, id, 1)};
}

std::uint8_t Recording::status(std::size_t frame, std::size_t id) const {
  const RecordedColumn* c = column("status");
  const double s = c ? at(*c, frame, id) : 0;
  return std::isnan(s) ? 3 : static_cast<std::uint8_t>(s);
}

std::size_t Recording::found_by_time(double t) const {
  return static_cast<std::size_t>(std::count_if(found_time.begin(), found_time.end(), [t](double f) { return f <= t; }));
}

Recording load_recording(const fs::path& folder) {
  const json manifest = finished_test(folder);
  Recording r;
  r.folder = folder;
  const json config = read_config(folder / "config.json");
  if (!config.is_object()) throw InputError(shown(folder / "config.json") + ": not a test (a JSON object)");
  r.test_name = config.contains("name") && config["name"].is_string() ? config["name"].get<std::string>() : folder.filename().string();
  r.seed = config.contains("seed") && config["seed"].is_number_unsigned() ? config["seed"].get<std::uint64_t>() : 0;
  r.dt = number_or(config, "dt", 0);
  r.log_interval = number_or(config, "log_interval", 0);
  r.duration = number_or(config, "time", 0);
  if (config.contains("versions") && config["versions"].is_object() && config["versions"].contains("salsa") && config["versions"]["salsa"].is_string())
    r.salsa_version = config["versions"]["salsa"].get<std::string>();
  r.map = read_map_file(folder / "map.json");
  std::vector<std::size_t> counts;
  r.groups = read_groups(config, r.map.spawn, counts);
  if (config.contains("targets") && config["targets"].is_object() && config["targets"].contains("params"))
    r.target_radius = number_or(config["targets"]["params"], "radius", 0);
  check_size(manifest, folder / "targets.csv");
  read_targets(r, folder / "targets.csv");

  std::error_code ec;
  if (const fs::path archive = folder / archive_name; fs::is_regular_file(archive, ec)) {
    check_size(manifest, archive);
    r.source = archive;
    read_archive(archive, r);
  } else if (const fs::path csv = folder / "drones.csv"; fs::is_regular_file(csv, ec)) {
    check_size(manifest, csv);
    r.source = csv;
    read_drones_csv(r, csv, counts);
  } else {
    throw InputError(shown(folder) + ": has neither " + archive_name + " nor drones.csv (run it again with --archive, or without --no-drones-csv)");
  }
  // A group started around the map's own spawn while the first group had a point of its own: the
  // map's spawn is not in the folder, so its base is where its drones were at time 0 (the disc's centre).
  std::map<std::size_t, std::pair<Vec2, double>> starts;
  if (const RecordedColumn* group = r.column("group"); group && r.frames() > 0)
    for (std::size_t id = 0; id < r.drones; ++id) {
      const double g = r.at(*group, 0, id);
      const Vec2 p = r.position(0, id);
      if (std::isnan(g) || std::isnan(p.x)) continue;
      auto& [sum, n] = starts[static_cast<std::size_t>(g)];
      sum = sum + p, n += 1;
    }
  for (std::size_t g = 0; g < r.groups.size(); ++g)
    if (std::isnan(r.groups[g].base.x)) {
      const auto it = starts.find(g);
      r.groups[g].base = it == starts.end() ? r.map.spawn : it->second.first / it->second.second;
    }

  return r;
}

}  // namespace salsa
