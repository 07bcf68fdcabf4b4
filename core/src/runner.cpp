#include "salsa/core/runner.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>

#include "salsa/core/metrics.hpp"
#include "salsa/core/names.hpp"
#include "running_notes.hpp"

namespace salsa {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

// ---- Data files

std::string header(std::string columns, const std::vector<std::string>& more) {
  for (const auto& c : more) columns += "," + c;
  return columns;
}

// summary.csv: one row per logged step, salsa's columns then the metrics'.
class SummaryObserver final : public Observer {
 public:
  SummaryObserver(const fs::path& file, MetricSet& metrics)
      : csv_(file, header(summary_columns, metrics.step_columns())), metrics_(metrics) {}
  void observe(const Simulation& sim) override {
    double sum = 0, top = 0;
    for (Vec2 v : sim.drone_velocities()) {
      const double s = v.length();
      sum += s;
      top = std::max(top, s);
    }
    double nn_sum = 0;
    std::size_t nn_count = 0;
    for (double d : sim.nearest_neighbour_distances())
      if (std::isfinite(d)) nn_sum += d, ++nn_count;
    const std::size_t n = sim.drone_count(), targets = sim.targets().size();
    csv_.field(sim.time(), 4).field(static_cast<std::uint64_t>(sim.targets_found()));
    csv_.field(targets ? static_cast<double>(sim.targets_found()) / static_cast<double>(targets) : 0.0, 6);
    csv_.field(n ? sum / static_cast<double>(n) : 0.0, 4).field(top, 4);
    if (nn_count) csv_.field(nn_sum / static_cast<double>(nn_count), 4);
    else csv_.empty_field();
    csv_.field(sim.collisions());
    metrics_.row(sim, csv_);
    csv_.end_row();
  }
  void close() { csv_.close(); }

 private:
  CsvWriter csv_;
  MetricSet& metrics_;
};

// drones.csv: one row per logged step and drone.
class DroneObserver final : public Observer {
 public:
  explicit DroneObserver(const fs::path& file) : csv_(file, "time,id,x,y,vx,vy") {}
  void observe(const Simulation& sim) override {
    const auto p = sim.drone_positions();
    const auto v = sim.drone_velocities();
    for (std::size_t i = 0; i < p.size(); ++i) {
      csv_.field(sim.time(), 4).field(static_cast<std::uint64_t>(i));
      csv_.field(p[i].x, 4).field(p[i].y, 4).field(v[i].x, 4).field(v[i].y, 4);
      csv_.end_row();
    }
  }
  void close() { csv_.close(); }

 private:
  CsvWriter csv_;
};

void write_targets(const fs::path& file, const Simulation& sim) {
  CsvWriter csv(file, "id,x,y,found_time,found_by,observations");
  const auto& targets = sim.targets();
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const TargetState& t = targets[i];
    csv.field(static_cast<std::uint64_t>(i)).field(t.position.x, 4).field(t.position.y, 4);
    if (t.found()) csv.field(t.found_time, 4).field(static_cast<std::uint64_t>(t.found_by));
    else csv.empty_field().empty_field();
    csv.field(t.observations);
    csv.end_row();
  }
  csv.close();
}

// map.json: the map the test ran on, in the map file format (docs/maps.md). One shape per line.
void append_number(std::string& out, double v) {
  if (v == 0) v = 0;  // no "-0": it would read back as the integer 0 anyway
  char text[32];
  out.append(text, std::to_chars(text, text + sizeof text, v).ptr);  // shortest text that reads back exactly
}

void append_point(std::string& out, Vec2 p) {
  out += '[';
  append_number(out, p.x);
  out += ", ";
  append_number(out, p.y);
  out += ']';
}

void append_shapes(std::string& out, const char* key, const std::vector<Polyline>& shapes, bool last) {
  out += "  \"";
  out += key;
  out += "\": [";
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    out += i ? ",\n    [" : "\n    [";
    for (std::size_t j = 0; j < shapes[i].size(); ++j) {
      if (j) out += ", ";
      append_point(out, shapes[i][j]);
    }
    out += ']';
  }
  out += shapes.empty() ? "]" : "\n  ]";
  out += last ? "\n" : ",\n";
}

/// Writes a whole small file and syncs it; WriteError naming the file on any failure.
void write_file(const fs::path& file, const std::string& text) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError(file.string() + ": cannot create file (" + std::strerror(errno) + ")");
  std::size_t done = 0;
  int error = 0;
  while (done < text.size() && !error) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n > 0) done += static_cast<std::size_t>(n);
    else if (n < 0 && errno != EINTR) error = errno;
  }
  if (!error && ::fsync(fd) != 0 && errno != EINVAL) error = errno;
  if (::close(fd) != 0 && !error) error = errno;
  if (error) throw WriteError(file.string() + ": write failed (disk full?): " + std::strerror(error));
}

void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// ---- Output folders: only folders carrying the marker are ever removed or replaced.

const char* marker_text = "This folder was written by salsa run (docs/output-format.md); salsa may replace it with --force.\n";

fs::path partial_folder(const fs::path& out, const std::string& name) { return out / ("." + name + ".partial"); }

bool exists_at_all(const fs::path& p) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(p, ec));
}

/// A real folder (not a symbolic link) holding the marker file.
bool salsa_wrote(const fs::path& folder) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(folder, ec)) && fs::is_regular_file(fs::symlink_status(folder / folder_marker, ec));
}

void remove_ours(const fs::path& folder) {
  if (!salsa_wrote(folder)) throw InputError(folder.string() + ": salsa did not write this folder (no " + folder_marker + " file), so it is left alone (remove or rename it yourself)");
  std::error_code ec;
  fs::remove_all(folder, ec);
  if (ec) throw WriteError(folder.string() + ": cannot remove folder (" + ec.message() + ")");
}

/// Why a leftover .partial folder cannot be cleaned up ("" when it can, or is absent).
std::string partial_problem(const fs::path& work) {
  if (!exists_at_all(work) || salsa_wrote(work)) return {};
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(work, ec)) && fs::is_empty(work, ec) && !ec) return {};  // cut off before its marker
  return work.string() + ": salsa did not write this (no " + folder_marker + " file), so it is left alone (remove or rename it yourself)";
}

void clean_partial(const fs::path& work) {
  if (const std::string why = partial_problem(work); !why.empty()) throw InputError(why);
  if (!exists_at_all(work)) return;
  std::error_code ec;
  fs::remove_all(work, ec);
  if (ec) throw WriteError(work.string() + ": cannot remove folder (" + ec.message() + ")");
}

// ---- --resume: a finished test is kept only when it is the test asked for now.

std::string shown(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "a list";
  const std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

/// The first difference between a finished test's config (there) and the one asked for (now), as
/// "seed is 3 there, 4 now", or "" when they are the same. Walks `now` (whose depth salsa made), so
/// a deeply nested file there cannot exhaust the stack.
std::string first_difference(const json& there, const json& now, const std::string& field) {
  const std::string name = field.empty() ? "the file" : field;
  if (now.is_object()) {
    if (!there.is_object()) return name + " is " + shown(there) + " there, an object now";
    for (const auto& [key, value] : now.items()) {
      const std::string sub = field.empty() ? key : field + "." + key;
      if (!there.contains(key)) return sub + " is missing there, " + shown(value) + " now";
      if (std::string d = first_difference(there[key], value, sub); !d.empty()) return d;
    }
    for (const auto& [key, value] : there.items())
      if (!now.contains(key)) return (field.empty() ? key : field + "." + key) + " is " + shown(value) + " there, not set now";
    return {};
  }
  if (now.is_array()) {
    if (!there.is_array()) return name + " is " + shown(there) + " there, a list now";
    if (there.size() != now.size())
      return name + " has " + std::to_string(there.size()) + " entries there, " + std::to_string(now.size()) + " now";
    for (std::size_t i = 0; i < now.size(); ++i)
      if (std::string d = first_difference(there[i], now[i], name + "[" + std::to_string(i) + "]"); !d.empty()) return d;
    return {};
  }
  if (there.is_structured() || there != now) return name + " is " + shown(there) + " there, " + shown(now) + " now";
  return {};
}

/// For a finished test's folder under --resume: "" when it holds the test asked for now (skip it),
/// else why it does not.
std::string resume_difference(const fs::path& folder, const std::string& config_now) {
  const fs::path file = folder / "config.json";
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) return file.string() + ": cannot be read";
  if (text.str() == config_now) return {};
  json there;
  try {
    there = json::parse(text.str());
  } catch (const std::exception&) {
    return file.string() + ": not valid JSON, so it cannot be the same test";
  }
  // Where a plugin was found is not what ran (its hash is): a moved plugin folder still resumes. In
  // place: a copy of a deeply nested file would recurse as deep.
  auto drop_plugin_paths = [](json& config) {
    if (config.is_object() && config.contains("versions") && config["versions"].is_object())
      for (auto& [kind, v] : config["versions"].items()) {
        if (v.is_object()) v.erase("file");
        if (v.is_array())
          for (json& e : v)
            if (e.is_object()) e.erase("file");
      }
  };
  json now = json::parse(config_now);
  drop_plugin_paths(there);
  drop_plugin_paths(now);
  const std::string d = first_difference(there, now, "");
  return d.empty() ? "" : file.string() + ": " + d;
}

/// Why this test may not write its folder ("" when it may, or when --resume will skip it).
std::string refusal(const TestSpec& test, const std::string& config, const RunOptions& options) {
  if (const std::string why = name_problem(test.name); !why.empty()) return test.source + ": name: " + why;
  const fs::path folder = options.out / test.name;
  if (const std::string why = partial_problem(partial_folder(options.out, test.name)); !why.empty()) return why;
  if (!exists_at_all(folder)) return {};
  const std::string replace = salsa_wrote(folder) ? "use --force to replace it"
                                                  : std::string("salsa did not write it (no ") + folder_marker + " file), so it is left alone";
  if (options.resume) {
    if (!exists_at_all(folder / "config.json")) {
      if (options.force && salsa_wrote(folder)) return {};
      return folder.string() + ": holds no finished test (no config.json), so --resume cannot skip it (" + replace + ")";
    }
    const std::string diff = resume_difference(folder, config);
    if (diff.empty() || (options.force && salsa_wrote(folder))) return {};
    return diff + "; --resume keeps only identical tests (" + replace + ")";
  }
  if (options.force) {
    if (salsa_wrote(folder)) return {};
    return folder.string() + ": --force replaces only folders salsa wrote, and this one has no " + folder_marker +
           " file (remove or rename it yourself)";
  }
  return folder.string() + ": already exists (allowed: a new folder; use --resume to skip finished tests or --force to replace them)";
}

/// What config.json holds. A map file's path is made absolute: a relative one would resolve against
/// config.json's own folder when it is rerun, not against the folder it was given in.
std::string config_of(const TestSpec& test, const PluginHost& host) {
  if (test.map_file.empty() || fs::path(test.map_file).is_absolute()) return resolved_json(test, host);
  TestSpec copy = test;
  copy.map_file = fs::absolute(test.map_file).lexically_normal().string();
  return resolved_json(copy, host);
}

std::string format_time(double t) {
  std::ostringstream s;
  s.precision(6);
  s << t;
  return s.str();
}

}  // namespace

// ---- Public

void check_outputs(const std::vector<TestSpec>& tests, const PluginHost& host, const RunOptions& options) {
  const fs::path& out = options.out;
  if (out.empty()) throw InputError("--out: \"\" is empty (allowed: a folder, created if missing)");
  std::error_code ec;
  if (const auto st = fs::status(out, ec); fs::exists(st) && !fs::is_directory(st))
    throw InputError("--out: " + out.string() + " is a file (allowed: a folder, created if missing)");
  // A test's config (JSON built through the host) only where --resume compares it with a finished one:
  // a queue of 10^6 new tests is checked with a few file-system calls each.
  for (const auto& t : tests) {
    const bool compared = options.resume && name_problem(t.name).empty() && exists_at_all(out / t.name / "config.json");
    if (const std::string why = refusal(t, compared ? config_of(t, host) : std::string(), options); !why.empty())
      throw InputError(why);
  }
  fs::create_directories(out, ec);
  if (ec) throw InputError("--out: " + out.string() + ": cannot create folder (" + ec.message() + ")");
}

std::string test_config(const TestSpec& test, const PluginHost& host) { return config_of(test, host); }

std::string map_json(const MapData& map, Vec2 spawn) {
  std::string out = "{\n  \"bounds\": {\"min\": ";
  append_point(out, map.bounds.min);
  out += ", \"max\": ";
  append_point(out, map.bounds.max);
  out += "},\n  \"spawn\": ";
  append_point(out, spawn);
  out += ",\n";
  append_shapes(out, "obstacles", map.obstacles, false);
  append_shapes(out, "hollow", map.hollow, false);
  append_shapes(out, "lines", map.lines, true);
  return out += "}\n";
}

void record_failure(const fs::path& out, const std::string& name, const std::string& line) {
  const fs::path work = partial_folder(out, name);
  if (!salsa_wrote(work)) return;
  std::string text = line;
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  try {
    write_file(work / "error.txt", text + "\n");
  } catch (const WriteError&) {  // a full disk: the failure is still reported on stderr
  }
}

bool already_done(const TestSpec& test, const PluginHost& host, const RunOptions& options) {
  const fs::path folder = options.out / test.name;
  return options.resume && name_problem(test.name).empty() && exists_at_all(folder / "config.json") &&
         resume_difference(folder, config_of(test, host)).empty();
}

RunResult run_test(const TestSpec& test, const PluginHost& host, const RunOptions& options) {
  RunResult result;
  // The runner's own check of the name, whatever the reader did: it becomes a path.
  if (const std::string why = name_problem(test.name); !why.empty()) throw InputError(test.source + ": name: " + why);
  result.folder = options.out / test.name;
  if (already_done(test, host, options)) {
    result.skipped = true;
    return result;
  }
  const std::string config = config_of(test, host);
  if (const std::string why = refusal(test, config, options); !why.empty()) throw InputError(why);

  // The .partial folder: a leftover one (an interrupted run) is cleaned up; the marker goes in first.
  const fs::path work = partial_folder(options.out, test.name);
  clean_partial(work);
  std::error_code ec;
  fs::create_directories(work, ec);
  if (ec) throw WriteError(work.string() + ": cannot create folder (" + ec.message() + ")");
  write_file(work / folder_marker, marker_text);

  NoteGuard guard{prepare_note(test, host, work)};
  // A failed test keeps its .partial folder, with error.txt saying why (one line).
  auto failed = [&](const std::string& line) {
    record_failure(options.out, test.name, line);
    return TestFailure(line);
  };
  const std::string where = "test '" + test.name + "' (" + test.source + ")";
  const std::string behavior = "behavior '" + test.behavior.name + "' (" + host.behavior(test.behavior.name).plugin().file.string() + ")";
  const auto start = std::chrono::steady_clock::now();
  {
    std::optional<Simulation> sim;
    std::optional<MetricSet> metrics;
    try {
      sim.emplace(make_setup(test, host, options.threads));
      metrics.emplace(test, host);
    } catch (const std::exception& e) {
      throw failed(where + ": could not start: " + e.what());
    }
    // The map the test runs on, for the plots and for rerunning it on the same geometry.
    try {
      write_file(work / "map.json", map_json(sim->map(), sim->spawn_point()));
    } catch (const WriteError& e) {
      record_failure(options.out, test.name, where + ": " + e.what());
      throw WriteError(where + ": " + e.what());
    }
    SummaryObserver summary(work / "summary.csv", *metrics);
    std::optional<DroneObserver> drones;
    if (options.drones_csv) drones.emplace(work / "drones.csv");
    sim->add_observer(&summary);
    if (drones) sim->add_observer(&*drones);
    try {
      metrics->start(*sim);
      summary.observe(*sim);  // time 0
    } catch (const MetricFailure& e) {
      throw failed(where + ": " + e.what() + " (rows so far in " + work.string() + ")");
    }
    if (drones) drones->observe(*sim);
    const std::size_t steps = test.steps();
    TestSpec changed = test;  // as the timed changes leave it
    std::size_t next_change = 0;
    const auto stepping = std::chrono::steady_clock::now();
    try {
      for (std::size_t i = 0; i < steps; ++i) {
        // Timed changes apply right before the step that starts at their time (as the GUI sandbox did).
        for (; next_change < test.changes.size() && change_step(test.changes[next_change].time, test.dt) <= i; ++next_change) {
          try {
            apply_change(*sim, changed, test.changes[next_change], host);
          } catch (const std::exception& e) {
            throw failed(where + ": the change at t = " + format_time(test.changes[next_change].time) + " s could not be applied: " +
                         e.what() + " (rows so far in " + work.string() + ")");
          }
        }
        if (const int sig = stop_requested.load(std::memory_order_relaxed)) {
          summary.close();
          if (drones) drones->close();
          throw Interrupted(signal_name(sig) + ": stopped " + where + " at t = " + format_time(sim->time()) +
                                " s; its rows so far are in " + work.string() + " (run again with --resume to redo it)",
                            sig);
        }
        sim->step();
        metrics->after_step(*sim);
        if (guard.note) guard.note->step.store(i + 1, std::memory_order_relaxed);
        if (options.progress) options.progress->store(i + 1, std::memory_order_relaxed);
        if (options.on_step) options.on_step(*sim);
      }
      result.stepping_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - stepping).count();
    } catch (const Interrupted&) {
      throw;
    } catch (const TestFailure&) {  // a change that could not be applied: already worded
      throw;
    } catch (const MetricFailure& e) {
      throw failed(where + ": " + e.what() + " (rows so far in " + work.string() + ")");
    } catch (const WriteError& e) {
      record_failure(options.out, test.name, where + ": " + e.what());
      throw WriteError(where + ": " + e.what());
    } catch (const std::exception& e) {
      throw failed(where + ": " + behavior + " failed at t = " + format_time(sim->time()) + " s: " + e.what() +
                        " (rows so far in " + work.string() + ")");
    }
    std::vector<std::pair<std::string, std::string>> finals;
    try {
      finals = metrics->finish(*sim);
    } catch (const MetricFailure& e) {
      throw failed(where + ": " + e.what() + " (rows so far in " + work.string() + ")");
    }
    try {
      summary.close();
      if (drones) drones->close();
      write_targets(work / "targets.csv", *sim);
      write_file(work / "outcome.csv", outcome_csv(*sim, finals));
    } catch (const WriteError& e) {
      record_failure(options.out, test.name, where + ": " + e.what());
      throw WriteError(where + ": " + e.what());
    }
    result.steps = steps;
    result.targets = sim->targets().size();
    result.found = sim->targets_found();
  }
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  try {
    std::ostringstream timing;
    timing.precision(6);
    timing << "{\"wall_seconds\": " << std::fixed << result.wall_seconds << ", \"steps\": " << result.steps << "}\n";
    write_file(work / "timing.json", timing.str());
    // config.json last: its presence marks a complete test (what --resume looks for).
    write_file(work / "config.json", config);
    sync_folder(work);
    if (exists_at_all(result.folder)) remove_ours(result.folder);  // --force, checked again just before
    fs::rename(work, result.folder, ec);
    if (ec) throw WriteError(result.folder.string() + ": cannot move " + work.string() + " there (" + ec.message() + ")");
    sync_folder(options.out);
  } catch (const WriteError& e) {
    record_failure(options.out, test.name, where + ": " + e.what());
    throw WriteError(where + ": " + e.what());
  }
  return result;
}

}  // namespace salsa
