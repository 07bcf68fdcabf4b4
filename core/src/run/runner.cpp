#include "salsa/core/run/runner.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>

#include "format.hpp"
#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/files/map_file.hpp"
#include "salsa/core/run/metrics.hpp"
#include "salsa/core/run/session.hpp"
#include "salsa/core/files/names.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "salsa/core/replay/archive.hpp"
#include "run/running_notes.hpp"

namespace salsa {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

// ---- Data files

std::string header(std::string columns, const std::vector<std::string>& more) {
  for (const auto& c : more) columns += "," + c;
  return columns;
}

// summary.csv: one row per logged step, salsa's columns, the metrics', then the test models'.
class SummaryObserver final : public Observer {
 public:
  /// The columns are the test's as it starts; the values read the session's test as timed changes left it.
  SummaryObserver(const fs::path& file, MetricSet& metrics, const Session& session)
      : outputs_(session.current()), csv_(file, header(header(summary_columns, metrics.step_columns()), outputs_.columns())),
        metrics_(metrics), session_(session) {}
  void observe(const Simulation& sim) override {
    const SummaryRow row = summary_row(sim);
    csv_.field(row.time, 4).field(static_cast<std::uint64_t>(row.targets_found)).field(row.fraction_found, 6);
    csv_.field(row.mean_speed, 4).field(row.max_speed, 4);
    if (std::isfinite(row.mean_nn_distance)) csv_.field(row.mean_nn_distance, 4);
    else csv_.empty_field();
    csv_.field(row.collisions);
    metrics_.row(sim, csv_);
    for (const std::string& text : outputs_.values(sim, session_.current())) csv_.text(text);
    csv_.end_row();
  }
  void close() { csv_.close(); }

 private:
  ModelOutputs outputs_;
  CsvWriter csv_;
  MetricSet& metrics_;
  const Session& session_;
};

// drones.csv: one row per logged step and drone not removed; with the fleet, its group, status and
// energy drawn; then the state columns asked for by name (RunOptions::drone_columns).
class DroneObserver final : public Observer {
 public:
  DroneObserver(const fs::path& file, bool fleet, bool charging, const std::vector<std::string>& columns)
      : csv_(file, header(fleet ? (charging ? "time,id,x,y,vx,vy,group,status,energy_used_Wh,charging_s" : "time,id,x,y,vx,vy,group,status,energy_used_Wh")
                                : "time,id,x,y,vx,vy",
                          drone_column_headers(columns))),
        fleet_(fleet), charging_(fleet && charging), columns_(columns) {
    for (const std::string& name : columns) widths_.push_back(width(name));
  }
  void observe(const Simulation& sim) override {
    const auto p = sim.drone_positions();
    const auto v = sim.drone_velocities();
    const auto status = sim.drone_status();
    std::vector<StateColumn> extra;
    for (const std::string& name : columns_) extra.push_back(sim.column(name));  // none yet: the wind's before it blew
    for (std::uint32_t i = 0; i < p.size(); ++i) {
      if (status[i] == DroneStatus::removed) continue;
      csv_.field(sim.time(), 4).field(static_cast<std::uint64_t>(i));
      csv_.field(p[i].x, 4).field(p[i].y, 4).field(v[i].x, 4).field(v[i].y, 4);
      if (fleet_) {
        csv_.text(sim.setup().groups[sim.drone_groups()[i]].name).text(status_name(sim, i));
        csv_.field(sim.energy_used(i) / 3600, 4);
        if (charging_) csv_.field(sim.charging_time(i), 4);
      }
      for (std::size_t k = 0; k < extra.size(); ++k) write_value(extra[k], widths_[k], i);
      csv_.end_row();
    }
  }
  void close() { csv_.close(); }

 private:
  static std::size_t width(const std::string& name) {
    for (const StateColumn& c : declared_drone_columns())
      if (c.name == name) return c.width;
    return 1;
  }
  /// Drone i's value(s) of `c` as written: whole numbers as they are, doubles in their shortest form that
  /// reads back exactly (a clock of 1e-7 keeps its digits); empty while the simulation keeps no such column.
  void write_value(const StateColumn& c, std::size_t width, std::uint32_t i) {
    for (std::size_t k = 0; k < width; ++k) {
      if (!c.data || i >= c.rows) {
        csv_.empty_field();
        continue;
      }
      const std::size_t at = i * c.width + k;
      if (c.type == StateColumn::Type::u8) csv_.field(std::uint64_t{static_cast<const std::uint8_t*>(c.data)[at]});
      else if (c.type == StateColumn::Type::u32) csv_.field(std::uint64_t{static_cast<const std::uint32_t*>(c.data)[at]});
      else {
        char text[32];
        const auto end = std::to_chars(text, text + sizeof text, static_cast<const double*>(c.data)[at]).ptr;
        csv_.text({text, static_cast<std::size_t>(end - text)});
      }
    }
  }

  CsvWriter csv_;
  bool fleet_, charging_;  ///< charging: return to base's time charged (s) after the energy
  std::vector<std::string> columns_;
  std::vector<std::size_t> widths_;
};

// trajectories.nc: archive_columns and the columns asked for by name, at every logged step.
class ArchiveObserver final : public Observer {
 public:
  ArchiveObserver(const fs::path& file, const TestSpec& test, const Simulation& sim, const std::string& config, const std::vector<std::string>& columns)
      : names_(recorded(columns)), archive_(file, provenance(test, sim, config, names_)) {}
  void observe(const Simulation& sim) override {
    std::vector<StateColumn> kept;
    for (const StateColumn& c : sim.columns())
      if (std::find(names_.begin(), names_.end(), c.name) != names_.end()) kept.push_back(c);
    archive_.frame(sim.time(), kept);
  }
  void close(const Simulation& sim) {
    const auto& kind = sim.setup().target_kind;
    archive_.close(sim.targets(), kind ? kind->radius() : 0);
  }

 private:
  /// archive_columns, then those named that it lacks.
  static std::vector<std::string> recorded(const std::vector<std::string>& named) {
    std::vector<std::string> names(std::begin(archive_columns), std::end(archive_columns));
    for (const std::string& name : named)
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    return names;
  }
  static ArchiveProvenance provenance(const TestSpec& test, const Simulation& sim, const std::string& config, const std::vector<std::string>& names) {
    ArchiveProvenance p{test.name, salsa_version(), config, test.seed, test.dt, test.log_interval, {}, most_drones(test), names};
    for (const auto& g : sim.setup().groups) p.groups.push_back(g.name);
    return p;
  }
  /// The most drone ids the test can have: every timed change that adds drones adds new ids.
  static std::size_t most_drones(const TestSpec& test) {
    TestSpec state = test;
    std::size_t ids = test.drone_total();
    for (const Change& c : test.changes) {
      const std::size_t before = state.drone_total();
      apply_to_test(state, c);
      ids += state.drone_total() > before ? state.drone_total() - before : 0;
    }
    return ids;
  }
  std::vector<std::string> names_;  ///< the columns it records
  ArchiveWriter archive_;
};

// fleet.csv: each drone at the end, removed ones too: its status, since when, energy and battery.
void write_fleet(const fs::path& file, const Simulation& sim, bool charging) {
  CsvWriter csv(file, charging ? "id,group,status,since,energy_used_Wh,battery_left,charging_s" : "id,group,status,since,energy_used_Wh,battery_left");
  const auto status = sim.drone_status();
  for (std::uint32_t i = 0; i < status.size(); ++i) {
    const std::uint32_t g = sim.drone_groups()[i];
    csv.field(static_cast<std::uint64_t>(i)).text(sim.setup().groups[g].name).text(status_name(sim, i));
    if (status[i] == DroneStatus::flying) csv.empty_field();
    else csv.field(sim.status_time(i), 4);
    csv.field(sim.energy_used(i) / 3600, 4);
    const double capacity = sim.drone_config(g).battery_capacity * 3600;
    if (capacity > 0) csv.field(std::clamp(sim.battery_left(i) / capacity, 0.0, 1.0), 4);
    else csv.empty_field();
    if (charging) csv.field(sim.charging_time(i), 4);
    csv.end_row();
  }
  csv.close();
}

// targets.csv: each target at the end; moving targets (x, y: where they ended) also where they were found.
void write_targets(const fs::path& file, const Simulation& sim) {
  const bool moving = sim.targets_move();
  CsvWriter csv(file, moving ? "id,x,y,found_time,found_by,observations,found_x,found_y" : "id,x,y,found_time,found_by,observations");
  const auto& targets = sim.targets();
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const TargetState& t = targets[i];
    csv.field(static_cast<std::uint64_t>(i)).field(t.position.x, 4).field(t.position.y, 4);
    if (t.found()) csv.field(t.found_time, 4).field(static_cast<std::uint64_t>(t.found_by));
    else csv.empty_field().empty_field();
    csv.field(t.observations);
    if (moving && t.found()) csv.field(t.found_position.x, 4).field(t.found_position.y, 4);
    else if (moving) csv.empty_field().empty_field();
    csv.end_row();
  }
  csv.close();
}


}  // namespace

// ---- Public

std::string drone_columns_problem(const std::vector<std::string>& names) {
  const std::vector<StateColumn> declared = declared_drone_columns();
  auto written = [](std::string_view name) { return name == "position" || name == "velocity" || name == "group" || name == "status"; };
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string& name = names[k];
    if (written(name))
      return "'" + name + "' is in drones.csv already (x, y, vx, vy; group and status with the fleet model)";
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(k), name) != names.begin() + static_cast<std::ptrdiff_t>(k))
      return "'" + name + "' is named twice";
    if (std::none_of(declared.begin(), declared.end(), [&](const StateColumn& c) { return c.name == name; })) {
      std::string allowed;
      for (const StateColumn& c : declared)
        if (!written(c.name)) allowed += (allowed.empty() ? "" : ", ") + std::string(c.name);
      return "'" + name + "' is not a drone state column (allowed: " + allowed + ")";
    }
  }
  return {};
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
  const std::string config = test_config(test, host);
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
  const std::string rows_so_far = " (rows so far in " + work.string() + ")";
  const std::string where = "test '" + test.name + "' (" + test.source + ")";
  auto write_failed = [&](const WriteError& e) {
    record_failure(options.out, test.name, where + ": " + e.what());
    return WriteError(where + ": " + e.what());
  };
  const auto start = std::chrono::steady_clock::now();
  {
    std::optional<Session> session;
    try {
      session.emplace(test, host, SessionOptions{options.threads, nullptr});
    } catch (const TestFailure& e) {
      throw failed(e.what());
    }
    Simulation& sim = session->simulation();
    // The map the test runs on, for the plots and for rerunning it on the same geometry.
    try {
      write_file(work / "map.json", map_json(sim.map(), sim.spawn_point()));
    } catch (const WriteError& e) {
      throw write_failed(e);
    }
    SummaryObserver summary(work / "summary.csv", session->metrics(), *session);
    std::optional<DroneObserver> drones;
    if (options.drones_csv) drones.emplace(work / "drones.csv", test.fleet(), test.return_to_base(), options.drone_columns);
    std::optional<ArchiveObserver> archive;
    try {
      if (test.archive) archive.emplace(work / archive_name, test, sim, config, options.drone_columns);
    } catch (const WriteError& e) {
      throw write_failed(e);
    }
    session->add_observer(&summary);
    if (drones) session->add_observer(&*drones);
    if (archive) session->add_observer(&*archive);
    try {
      summary.observe(sim);  // time 0
    } catch (const MetricFailure& e) {
      throw failed(where + ": " + e.what() + rows_so_far);
    }
    if (drones) drones->observe(sim);
    try {
      if (archive) archive->observe(sim);
    } catch (const WriteError& e) {
      throw write_failed(e);
    }
    const auto stepping = std::chrono::steady_clock::now();
    try {
      while (!session->finished()) {
        if (const int sig = stop_requested.load(std::memory_order_relaxed)) {
          summary.close();
          if (drones) drones->close();
          throw Interrupted(signal_name(sig) + ": stopped " + where + " at t = " + format::seconds(sim.time()) +
                                " s; its rows so far are in " + work.string() + " (run again with --resume to redo it)",
                            sig);
        }
        session->step();
        const std::uint64_t done = sim.step_count();
        if (guard.note) guard.note->step.store(done, std::memory_order_relaxed);
        if (options.progress) options.progress->store(done, std::memory_order_relaxed);
        if (options.on_step) options.on_step(sim);
      }
      result.stepping_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - stepping).count();
    } catch (const TestFailure& e) {
      throw failed(e.what() + rows_so_far);
    } catch (const WriteError& e) {
      throw write_failed(e);
    }
    std::vector<std::pair<std::string, std::string>> finals;
    try {
      finals = session->finish();
    } catch (const TestFailure& e) {
      throw failed(e.what() + rows_so_far);
    }
    try {
      summary.close();
      if (drones) drones->close();
      if (archive) archive->close(sim);
      write_targets(work / "targets.csv", sim);
      if (test.fleet()) write_fleet(work / "fleet.csv", sim, test.return_to_base());
      const ModelOutputs outputs(test);
      const std::vector<std::string> texts = outputs.values(sim, session->current());
      for (std::size_t k = 0; k < texts.size(); ++k) finals.emplace_back(outputs.columns()[k], texts[k]);
      write_file(work / "outcome.csv", outcome_csv(sim, finals));
    } catch (const WriteError& e) {
      throw write_failed(e);
    }
    result.steps = test.steps();
    result.targets = sim.targets().size();
    result.found = sim.targets_found();
  }
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  try {
    std::ostringstream timing;
    timing.precision(6);
    timing << "{\"wall_seconds\": " << std::fixed << result.wall_seconds << ", \"steps\": " << result.steps << "}\n";
    write_file(work / "timing.json", timing.str());
    write_manifest(work, config);  // what --resume checks the folder against
    // config.json last: its presence marks a complete test (what --resume looks for).
    write_file(work / "config.json", config);
    sync_folder(work);
    if (exists_at_all(result.folder)) remove_ours(result.folder);  // --force, checked again just before
    fs::rename(work, result.folder, ec);
    if (ec) throw WriteError(result.folder.string() + ": cannot move " + work.string() + " there (" + ec.message() + ")");
    sync_folder(options.out);
  } catch (const WriteError& e) {
    throw write_failed(e);
  }
  return result;
}

}  // namespace salsa
