#include "salsa/core/experiments/queue_summary.hpp"

#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <functional>
#include <unordered_map>
#include <cerrno>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/files/names.hpp"
#include "salsa/core/files/output_folder.hpp"
#include "salsa/core/run/runner.hpp"

namespace salsa {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

// ---- Small helpers

/// FNV-1a, 64 bits: a stable hash (the same on every machine and release) for names of conditions.
std::uint64_t fnv1a(const std::string& text, std::uint64_t h = 14695981039346656037ull) {
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

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
    std::uint64_t h = fnv1a("cell apart from conditions");
    for (const std::string& c : kept) h = fnv1a(c + '\0' + text(r, c) + '\0', h);
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
  return hex(fnv1a(config.dump()), 12);
}

void for_each_test_config(const std::vector<TestSpec>& tests, const PluginHost& host,
                          const std::function<void(std::size_t, const std::string&)>& fn) {
  // A queue's repeats differ in name, seed and repeat alone: each such group builds its config once
  // through the host (JSON: the costly part, ~50 µs), and its other tests get that text with their
  // three top-level lines ("name", "seed", "repeat": indented 2, nothing nested is) replaced.
  struct Template {
    const TestSpec* test;
    std::string text;
    std::array<std::pair<std::size_t, std::size_t>, 3> values;  // [begin, end) of name, seed, repeat
  };
  std::vector<Template> templates;
  std::unordered_multimap<std::size_t, std::size_t> groups;
  auto key = [](const TestSpec& t) {
    std::size_t h = std::hash<std::string>{}(t.groups[0].behavior.name);
    auto mix = [&h](std::size_t v) { h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2); };
    mix(t.drone_total()), mix(t.targets), mix(std::hash<double>{}(t.time)), mix(std::hash<std::string>{}(t.map.name));
    std::vector<const PluginChoice*> choices{&t.map, &t.target};
    for (const GroupSpec& g : t.groups) choices.push_back(&g.behavior);
    for (const PluginChoice* c : choices)
      for (const auto& [name, value] : c->params.items()) mix(std::hash<double>{}(value));
    return h;
  };
  auto same_group = [](const TestSpec& a, const TestSpec& b) {
    TestSpec x = a;
    x.name = b.name, x.source = b.source, x.seed = b.seed, x.seed_given = b.seed_given, x.repeat = b.repeat;
    return x == b;
  };
  auto values_of = [](const TestSpec& t) {
    return std::array<std::string, 3>{json(t.name).dump(), std::to_string(t.seed), std::to_string(t.repeat)};
  };
  std::string text;
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const TestSpec& t = tests[i];
    const std::size_t k = key(t);
    const Template* found = nullptr;
    for (auto [it, end] = groups.equal_range(k); it != end && !found; ++it)
      if (same_group(*templates[it->second].test, t)) found = &templates[it->second];
    if (found) {
      const auto values = values_of(t);
      text.clear();
      std::size_t at = 0;
      for (std::size_t v = 0; v < 3; ++v) {
        text.append(found->text, at, found->values[v].first - at).append(values[v]);
        at = found->values[v].second;
      }
      text.append(found->text, at);
      fn(i, text);
      continue;
    }
    Template made{&t, test_config(t, host), {}};
    const auto values = values_of(t);
    bool usable = true;
    std::size_t from = 0;
    for (std::size_t v = 0; v < 3 && usable; ++v) {  // in the order resolved_json writes them
      const std::string line = std::string("\n  \"") + (v == 0 ? "name" : v == 1 ? "seed" : "repeat") + "\": ";
      const std::size_t begin = made.text.find(line, from);
      usable = begin != std::string::npos && made.text.compare(begin + line.size(), values[v].size(), values[v]) == 0;
      if (usable) made.values[v] = {begin + line.size(), begin + line.size() + values[v].size()}, from = made.values[v].second;
    }
    fn(i, made.text);
    if (!usable) continue;  // not as expected: this group's tests are built one by one
    groups.emplace(k, templates.size());
    templates.push_back(std::move(made));
  }
}

QueueRecord queue_record(const std::vector<TestSpec>& tests, const PluginHost& host, std::vector<std::string> command) {
  QueueRecord r;
  r.tests.reserve(tests.size());
  for (const auto& t : tests) r.tests.push_back(t.name);
  std::uint64_t h = fnv1a("");
  for_each_test_config(tests, host, [&](std::size_t, const std::string& config) { h = fnv1a(config + '\0', h); });
  r.configs_hash = hex(h, 16);
  r.command = std::move(command);
  return r;
}

namespace {

json record_json(const QueueRecord& record) {
  json out = {{"tests", record.tests}, {"configs_hash", record.configs_hash}, {"command", record.command}};
  if (!record.reference.empty()) out["reference"] = record.reference;  // only then: queue.json as before references
  if (record.top > 0) out["top"] = record.top;
  return out;
}

/// Whether OUT/queue.json exists, and then whether it records the same queue.
std::optional<bool> same_queue(const fs::path& file, const json& record, std::optional<json>& there) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(file, ec))) return std::nullopt;
  there = read_json(file);
  return there && there->is_object() && there->value("tests", json()) == record["tests"] &&
         there->value("configs_hash", json()) == record["configs_hash"] && there->value("reference", json()) == record.value("reference", json()) &&
         there->value("top", json()) == record.value("top", json());
}

}  // namespace

void check_queue_folder(const fs::path& out, const QueueRecord& record, bool resume, bool force) {
  const fs::path file = out / "queue.json";
  const json text = record_json(record);
  std::optional<json> there;
  const auto same = same_queue(file, text, there);
  if (!same || *same || resume || force) return;
  std::string what = "holds the results of another queue";
  if (!there || !there->is_object() || !there->contains("tests")) what = "is not a queue record salsa wrote";
  else if (there->value("tests", json()) == text["tests"]) what = "holds the same tests with other settings (another seed, time, parameter...)";
  throw InputError(file.string() + ": " + what + " (allowed: another --out folder; --resume to keep its finished tests that match, --force to replace them)");
}

void claim_queue_folder(const fs::path& out, const QueueRecord& record, bool resume, bool force) {
  check_queue_folder(out, record, resume, force);
  const fs::path file = out / "queue.json";
  const json text = record_json(record);
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::optional<json> there;
    if (const auto same = same_queue(file, text, there)) {
      if (*same) return;
      // Another queue's record: written meanwhile by another run (the second attempt) is refused like
      // one found at the start; only --resume or --force make it this queue's.
      if (attempt > 0) check_queue_folder(out, record, resume, force);
      replace_file(file, text.dump(2) + "\n");
      return;
    }
    // Absent: written under a temporary name and linked into place, so one of several shards wins.
    const fs::path tmp = file.string() + "." + std::to_string(::getpid()) + ".tmp";
    replace_file(tmp, text.dump(2) + "\n");
    const int linked = ::link(tmp.c_str(), file.c_str());
    const int error = errno;
    std::error_code ec;
    fs::remove(tmp, ec);
    if (linked == 0) return;
    if (error != EEXIST) throw WriteError(file.string() + ": cannot write (" + std::strerror(error) + ")");
  }
}

bool holds_results(const fs::path& out) {
  if (const auto record = read_json(out / "queue.json"); record && record->is_object() && record->contains("configs_hash")) return true;
  std::error_code ec;
  for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec))
    if (salsa_wrote(it->path())) return true;
  return false;
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
      // Without the plugin's declarations the defaults are unknown: the bare name, not "(defaults)".
      const std::string one = declared || !changed.empty() ? variant_label(behavior, changed) : behavior;
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
