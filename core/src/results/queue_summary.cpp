// OUT/summary.csv (one row per test: its config.json's inputs, its outcome) and timing.csv, from the test folders alone.
#include "salsa/core/results/queue_summary.hpp"

#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/files/names.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "salsa/core/run/runner.hpp"
#include "experiments/fnv1a.hpp"
#include "results/queue_folder.hpp"

namespace salsa {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace detail {

std::string hex(std::uint64_t v, int digits) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return std::string(text + 16 - digits);
}

std::optional<std::string> read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::optional<json> read_json(const fs::path& file) {
  const auto text = read_text(file);
  if (!text) return std::nullopt;
  try {
    return json::parse(*text);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace detail

using detail::fnv1a64;
using detail::hex;
using detail::read_json;
using detail::read_text;

namespace {

// ---- Small helpers

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return quoted + "\"";
}

/// The fields of one CSV line (quotes as csv_field writes them).
std::vector<std::string> csv_split(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') fields.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else fields.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

/// A JSON value as a CSV cell: numbers as config.json writes them, lists of plain values joined by ';'.
std::string cell_text(const json& v) {
  if (v.is_null()) return {};
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array() && std::none_of(v.begin(), v.end(), [](const json& e) { return e.is_structured(); })) {
    std::string joined;
    for (const auto& e : v) joined += (joined.empty() ? "" : ";") + cell_text(e);
    return joined;
  }
  return v.dump();
}

// ---- One test's row

struct Row {
  std::string name, status, error;
  std::string wall_seconds;                  // timing.json's, for OUT/timing.csv
  std::map<std::string, std::string> cells;  // column -> text
  std::vector<std::pair<std::string, json>> behaviors;  // for the variant: (group name with groups, else "", behavior object)
  std::string behavior;
};

void flatten(const json& v, const std::string& prefix, std::vector<std::pair<std::string, std::string>>& out) {
  if (v.is_object() && !v.empty()) {
    for (const auto& [key, value] : v.items()) flatten(value, prefix + "." + key, out);
    return;
  }
  out.emplace_back(prefix, cell_text(v));
}

/// "flocking 0.1.0" for {"plugin": "flocking", "version": "0.1.0"}; lists joined by ';'.
std::string version_text(const json& v) {
  if (v.is_object() && v.contains("plugin") && v.contains("version")) {
    // "flocking 0.1.0 #1a2b3c4d5e6f": the hash's start tells two builds of one version apart.
    std::string text = cell_text(v["plugin"]) + " " + cell_text(v["version"]);
    if (v.contains("sha256") && v["sha256"].is_string()) text += " #" + v["sha256"].get<std::string>().substr(0, 12);
    return text;
  }
  if (v.is_array()) {
    std::string joined;
    for (const auto& e : v) joined += (joined.empty() ? "" : ";") + version_text(e);
    return joined;
  }
  return cell_text(v);
}

/// Every input of config.json as (column, text), in the file's order. The fixed columns get their own
/// names (behavior, drones, targets, target, map, time, seed, repeat); parameters become
/// behavior.<p>, map.<p>, target.<p>.
std::vector<std::pair<std::string, std::string>> inputs_of(const json& config) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [key, value] : config.items()) {
    if (key == "name") continue;
    if ((key == "behavior" || key == "map" || key == "targets") && value.is_object()) {
      const std::string group = key == "targets" ? "target" : key;
      for (const auto& [k, v] : value.items()) {
        if (key == "behavior" && k == "label") continue;  // the variant column's
        if (k == "name" || (key == "targets" && k == "kind")) out.emplace_back(group, cell_text(v));
        else if (key == "targets" && k == "count") out.emplace_back("targets", cell_text(v));
        else if (k == "params" && v.is_object())
          for (const auto& [p, pv] : v.items()) out.emplace_back(group + "." + p, cell_text(pv));
        else flatten(v, group + "." + k, out);
      }
    } else if ((key == "metrics" || key == "contact_handlers") && value.is_array()) {
      // metrics = the names joined by ';', each parameter as metric.<name>.<p>; contact handlers alike
      // (contact_handler.<name>.<p>)
      const std::string each = key == "metrics" ? "metric." : "contact_handler.";
      std::string names;
      for (const auto& m : value) {
        const std::string name = m.is_object() ? cell_text(m.value("name", json())) : cell_text(m);
        names += (names.empty() ? "" : ";") + name;
        if (m.is_object() && m.contains("params") && m["params"].is_object())
          for (const auto& [p, pv] : m["params"].items()) out.emplace_back(each + name + "." + p, cell_text(pv));
      }
      out.emplace_back(key, names);
    } else if (key == "groups" && value.is_array()) {
      // Each group's fields under its name (groups.<name>.behavior, groups.<name>.behavior.<p>, ...),
      // and "drones" the whole swarm.
      std::uint64_t drones = 0;
      for (const json& g : value) {
        if (!g.is_object()) continue;
        const std::string at = "groups." + cell_text(g.value("name", json())) + ".";
        for (const auto& [k, v] : g.items()) {
          if (k == "name") continue;
          if (k == "behavior" && v.is_object()) {
            out.emplace_back(at + "behavior", cell_text(v.value("name", json())));
            if (v.contains("params") && v["params"].is_object())
              for (const auto& [p, pv] : v["params"].items()) out.emplace_back(at + "behavior." + p, cell_text(pv));
          } else {
            flatten(v, at + k, out);
          }
        }
        if (g.contains("drones") && g["drones"].is_number_unsigned()) drones += g["drones"].get<std::uint64_t>();
      }
      out.emplace_back("drones", std::to_string(drones));
    } else if (key == "condition" && value.is_object()) {
      out.emplace_back("condition", cell_text(value.value("name", json())));
      out.emplace_back("condition_label", cell_text(value.value("label", json())));
    } else if (key == "versions" && value.is_object()) {
      for (const auto& [k, v] : value.items()) out.emplace_back("versions." + k, version_text(v));
    } else {
      flatten(value, key, out);
    }
  }
  return out;
}

const std::vector<std::string> fixed_columns{"name", "status", "error", "cell", "variant", "condition", "condition_label", "behavior",
                                             "repeat", "seed", "drones", "targets", "target", "map", "time"};

/// Whether a column describes the behavior (what the paired comparison compares), not the cell.
bool behavior_column(const std::string& c) {
  if (c == "behavior" || c.starts_with("behavior.") || c == "versions.behavior" || c == "versions.behaviors") return true;
  if (!c.starts_with("groups.")) return false;
  const std::size_t dot = c.find('.', 7);
  return dot != std::string::npos && (c.compare(dot, std::string::npos, ".behavior") == 0 || c.compare(dot + 1, 9, "behavior.") == 0);
}

/// With conditions, the cell is the setting apart from the behavior and the condition: a hash of the
/// input columns but the behavior's, name, seed, repeat and those a condition sets (seen as the columns
/// that are the same within each condition and differ between conditions). So the cells of two conditions
/// are the same where the sweep gave them the same values, and the comparison pairs across them.
void cells_apart_from_conditions(std::vector<Row>& rows, const std::vector<std::string>& input_columns) {
  std::set<std::string> conditions;
  for (const Row& r : rows)
    if (r.status == "ok") conditions.insert(r.cells.count("condition") ? r.cells.at("condition") : "");
  if (conditions.size() < 2) return;
  std::vector<std::string> columns;
  for (const char* c : {"drones", "targets", "target", "map", "time"}) columns.push_back(c);
  columns.insert(columns.end(), input_columns.begin(), input_columns.end());
  auto text = [](const Row& r, const std::string& c) {
    const auto it = r.cells.find(c);
    return it == r.cells.end() ? std::string() : it->second;
  };
  std::sort(columns.begin(), columns.end());  // the same ids whichever tests are done
  std::vector<std::string> kept;
  for (const std::string& c : columns) {
    if (behavior_column(c) || c == "condition_label") continue;
    std::map<std::string, std::set<std::string>> by_condition;
    std::set<std::string> all;
    for (const Row& r : rows)
      if (r.status == "ok") by_condition[text(r, "condition")].insert(text(r, c)), all.insert(text(r, c));
    const bool condition_set = all.size() > 1 && std::all_of(by_condition.begin(), by_condition.end(), [](const auto& v) { return v.second.size() == 1; });
    if (!condition_set) kept.push_back(c);
  }
  for (Row& r : rows) {
    if (r.status != "ok") continue;
    std::uint64_t h = fnv1a64("cell apart from conditions");
    for (const std::string& c : kept) h = fnv1a64(c + '\0' + text(r, c) + '\0', h);
    r.cells["cell"] = hex(h, 12);
  }
}

/// Where an input column goes: behavior.*, map.*, drone.*, the other inputs, versions.*.
int group_of(const std::string& column) {
  if (column.starts_with("behavior.")) return 0;
  if (column.starts_with("map.")) return 1;
  if (column.starts_with("drone.")) return 2;
  if (column.starts_with("versions.")) return 4;
  return 3;
}

/// The test names of OUT: queue.json's list in its order, else every folder salsa wrote, by name.
std::vector<std::string> names_in(const fs::path& out) {
  if (const auto record = read_json(out / "queue.json"); record && record->contains("tests") && (*record)["tests"].is_array()) {
    std::vector<std::string> names;
    for (const auto& n : (*record)["tests"])
      if (n.is_string()) names.push_back(n.get<std::string>());
    return names;
  }
  std::set<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(out, ec)) {
    std::string name = entry.path().filename().string();
    if (!fs::is_regular_file(entry.path() / folder_marker, ec)) continue;
    if (name.starts_with(".") && name.ends_with(".partial")) name = name.substr(1, name.size() - 1 - 8);
    names.insert(name);
  }
  return {names.begin(), names.end()};
}

}  // namespace

void replace_file(const fs::path& file, const std::string& text) {
  const fs::path tmp = file.string() + "." + std::to_string(::getpid()) + ".tmp";
  try {
    write_file(tmp, text);
  } catch (const WriteError&) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw WriteError(file.string() + ": cannot write (" + write_failure(ec.value()) + ")");
  }
}

std::string cell_of(const std::string& config_json) {
  json config = json::parse(config_json);
  for (const char* key : {"behavior", "name", "seed", "repeat"}) config.erase(key);
  if (config.contains("groups") && config["groups"].is_array())  // the behaviors are what a cell compares
    for (json& g : config["groups"])
      if (g.is_object()) g.erase("behavior");
  if (config.contains("versions") && config["versions"].is_object()) {
    config["versions"].erase("behavior");
    config["versions"].erase("behaviors");
    // Where a plugin was found is not the condition (its version and hash are): the same queue run
    // from another install or build folder gets the same cells.
    for (auto& [kind, v] : config["versions"].items()) {
      if (v.is_object()) v.erase("file");
      if (v.is_array())
        for (json& e : v)
          if (e.is_object()) e.erase("file");
    }
  }
  return hex(fnv1a64(config.dump()), 12);
}

void write_queue_summary(const fs::path& out, const PluginHost* host) {
  // OUT's summary.csv and comparison.csv are replaced: only in a folder salsa wrote results into.
  if (!holds_results(out))
    throw InputError(out.string() + ": holds no salsa results (no queue.json record, no test folder with a " + folder_marker +
                     " file), so its files are left alone (allowed: a folder 'salsa run --out' wrote)");
  std::vector<Row> rows;
  std::vector<std::string> input_columns, outcome_names;
  std::set<std::string> seen_inputs, seen_outcomes;
  for (const std::string& name : names_in(out)) {
    Row row;
    row.name = name;
    const fs::path folder = out / name;
    const auto config_text = test_name_problem(name).empty() ? read_text(folder / "config.json") : std::nullopt;
    std::optional<json> config;
    if (config_text) try {
        config = json::parse(*config_text);
      } catch (const std::exception&) {
      }
    if (config && config->is_object()) {
      row.status = "ok";
      // Its data as written: a file deleted or cut since makes the row incomplete, saying which.
      if (std::string missing = data_problem(folder, false); !missing.empty()) row.status = "incomplete", row.error = std::move(missing);
      row.cells["cell"] = cell_of(*config_text);
      for (auto& [column, text] : inputs_of(*config)) {
        if (std::find(fixed_columns.begin(), fixed_columns.end(), column) == fixed_columns.end() && seen_inputs.insert(column).second)
          input_columns.push_back(column);
        row.cells[column] = std::move(text);
      }
      if (config->contains("behavior") && (*config)["behavior"].is_object()) {
        row.behavior = (*config)["behavior"].value("name", "");
        row.behaviors.emplace_back("", (*config)["behavior"]);
      } else if (config->contains("groups") && (*config)["groups"].is_array()) {
        // Groups: the behaviors of every group, "scouts=flocking / base=random_walk"; their parameters
        // are in the groups.<name>.behavior.<p> columns.
        const json& groups = (*config)["groups"];
        for (const json& g : groups)
          if (g.is_object() && g.contains("behavior") && g["behavior"].is_object()) {
            const std::string group = groups.size() > 1 ? cell_text(g.value("name", json())) : "";
            row.behavior += (row.behavior.empty() ? "" : " / ") + (group.empty() ? "" : group + "=") + cell_text(g["behavior"].value("name", json()));
            row.behaviors.emplace_back(group, g["behavior"]);
          }
        row.cells["behavior"] = row.behavior;
      }
      if (const auto outcome = read_text(folder / "outcome.csv")) {
        std::istringstream lines(*outcome);
        std::string header, values;
        std::getline(lines, header);
        std::getline(lines, values);
        const auto columns = csv_split(header), fields = csv_split(values);
        for (std::size_t i = 0; i < columns.size() && !columns[i].empty(); ++i) {
          if (seen_outcomes.insert(columns[i]).second) outcome_names.push_back(columns[i]);
          row.cells["outcome:" + columns[i]] = i < fields.size() ? fields[i] : "";
        }
      }
      if (const auto timing = read_json(folder / "timing.json"); timing && timing->contains("wall_seconds"))
        row.wall_seconds = cell_text((*timing)["wall_seconds"]);
    } else if (const auto error = read_text(out / ("." + name + ".partial") / "error.txt")) {
      row.status = "failed";
      row.error = error->substr(0, error->find('\n'));
    } else {
      row.status = "missing";
    }
    rows.push_back(std::move(row));
  }
  // config.json names the physics only when it is light (a Box2D test's file is as it always was): once
  // a queue has a light test, its Box2D rows say so too.
  if (seen_inputs.count("physics"))
    for (Row& r : rows)
      if (r.status == "ok" && !r.cells.count("physics")) r.cells["physics"] = "box2d";

  // The variant: each behavior and its non-default parameters (the plugin's defaults when the host
  // has it, else the parameters whose values differ within the queue), as variant_label words them.
  std::map<std::string, std::map<std::string, std::set<std::string>>> values_seen;  // behavior -> param -> values
  auto params_of = [](const json& behavior) { return behavior.value("params", json::object()); };
  for (const auto& r : rows)
    for (const auto& [group, b] : r.behaviors) {
      const json params = params_of(b);
      for (const auto& [p, v] : params.items()) values_seen[cell_text(b.value("name", json()))][p].insert(v.dump());
    }
  for (auto& r : rows) {
    if (r.status != "ok") continue;
    std::string label;
    for (const auto& [group, b] : r.behaviors) {
      const std::string behavior = cell_text(b.value("name", json()));
      const Parameters* declared = nullptr;
      if (host) try {
          declared = &host->behavior(behavior).factory.parameters;
        } catch (const std::exception&) {
        }
      std::vector<std::pair<std::string, std::string>> changed;
      const json params = params_of(b);
      for (const auto& [p, v] : params.items()) {
        bool differs = values_seen[behavior][p].size() > 1;
        if (declared) {
          const std::string& name = p;  // clang 14 cannot capture a structured binding
          const auto d = std::find_if(declared->begin(), declared->end(), [&](const Parameter& x) { return x.name == name; });
          differs = d == declared->end() || !v.is_number() || v.get<double>() != d->value;
        }
        if (differs) changed.emplace_back(p, v.is_number() ? Parameter::format(v.get<double>()) : cell_text(v));
      }
      // Without the plugin's declarations the defaults are unknown: the bare name, not "(defaults)". The
      // file's own label, when it gave one, says it all.
      const std::string one = b.contains("label") ? cell_text(b["label"]) : declared || !changed.empty() ? variant_label(behavior, changed) : behavior;
      label += (label.empty() ? "" : " / ") + (group.empty() ? "" : group + "=") + one;
    }
    r.cells["variant"] = label;
  }
  cells_apart_from_conditions(rows, input_columns);

  std::stable_sort(input_columns.begin(), input_columns.end(),
                   [](const std::string& a, const std::string& b) { return group_of(a) < group_of(b); });
  std::string text;
  auto header = [&](const std::string& c) { text += (text.empty() ? "" : ",") + csv_field(c); };
  for (const auto& c : fixed_columns) header(c);
  for (const auto& c : input_columns) header(c);
  // outcome.csv's columns keep their names, but for one an input column has already (e.g. targets).
  for (const auto& c : outcome_names) {
    const bool taken = std::find(fixed_columns.begin(), fixed_columns.end(), c) != fixed_columns.end() ||
                       std::find(input_columns.begin(), input_columns.end(), c) != input_columns.end();
    header(taken ? "outcome." + c : c);
  }
  text += "\n";
  std::string timing = "name,wall_seconds\n";  // apart: the only numbers that differ between identical runs
  for (const auto& r : rows) {
    std::string line = csv_field(r.name) + "," + r.status + "," + csv_field(r.error);
    auto cell = [&](const std::string& key) {
      const auto it = r.cells.find(key);
      line += "," + (it == r.cells.end() ? std::string() : csv_field(it->second));
    };
    for (std::size_t i = 3; i < fixed_columns.size(); ++i) cell(fixed_columns[i]);
    for (const auto& c : input_columns) cell(c);
    for (const auto& c : outcome_names) cell("outcome:" + c);
    text += line + "\n";
    if (!r.wall_seconds.empty()) timing += csv_field(r.name) + "," + r.wall_seconds + "\n";
  }
  replace_file(out / "summary.csv", text);
  replace_file(out / "timing.csv", timing);
}

}  // namespace salsa
