#include "salsa/core/runner.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>

#include "salsa/core/csv_writer.hpp"

namespace salsa {

namespace fs = std::filesystem;

namespace {

// summary.csv: one row per logged step.
class SummaryObserver final : public Observer {
 public:
  explicit SummaryObserver(const fs::path& file)
      : csv_(file, "time,targets_found,fraction_found,mean_speed,max_speed,mean_nn_distance,collisions") {}
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
    csv_.end_row();
  }
  void close() { csv_.close(); }

 private:
  CsvWriter csv_;
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

fs::path partial_folder(const fs::path& out, const std::string& name) { return out / ("." + name + ".partial"); }

/// Why a test's existing output folder may not be written to ("" when it may).
std::string refusal(const fs::path& folder, const RunOptions& options) {
  if (options.force || !fs::exists(folder)) return {};
  if (!options.resume)
    return folder.string() + ": already exists (allowed: a new folder; use --resume to skip finished tests or --force " +
           "to replace them)";
  if (!fs::exists(folder / "config.json"))
    return folder.string() + ": already exists but holds no finished test (no config.json), so --resume cannot skip it " +
           "(allowed: a finished test's folder or a new folder; use --force to replace it)";
  return {};
}

}  // namespace

void check_outputs(const std::vector<TestSpec>& tests, const RunOptions& options) {
  for (const auto& t : tests)
    if (const std::string why = refusal(options.out / t.name, options); !why.empty()) throw InputError(why);
}

RunResult run_test(const TestSpec& test, const PluginHost& host, const RunOptions& options) {
  RunResult result;
  result.folder = options.out / test.name;
  if (options.resume && fs::exists(result.folder / "config.json")) {
    result.skipped = true;
    return result;
  }
  if (const std::string why = refusal(result.folder, options); !why.empty()) throw InputError(why);

  // Everything that can fail on bad input fails here, before a file is written.
  SimulationSetup setup = make_setup(test, host, options.threads);
  const std::string config = resolved_json(test, host);

  const fs::path work = partial_folder(options.out, test.name);
  fs::remove_all(work);
  fs::create_directories(work);
  const auto start = std::chrono::steady_clock::now();
  {
    Simulation sim(std::move(setup));
    SummaryObserver summary(work / "summary.csv");
    std::optional<DroneObserver> drones;
    if (options.drones_csv) drones.emplace(work / "drones.csv");
    sim.add_observer(&summary);
    if (drones) sim.add_observer(&*drones);
    summary.observe(sim);  // time 0
    if (drones) drones->observe(sim);
    const std::size_t steps = test.steps();
    try {
      sim.run_steps(steps);
    } catch (const std::exception& e) {
      throw std::runtime_error(test.source + ": behavior '" + test.behavior.name + "' failed at t = " +
                               std::to_string(sim.time()) + " s: " + e.what());
    }
    summary.close();
    if (drones) drones->close();
    write_targets(work / "targets.csv", sim);
    result.steps = steps;
    result.targets = sim.targets().size();
    result.found = sim.targets_found();
  }
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // config.json last: its presence marks a complete test (what --resume looks for).
  {
    std::ofstream out(work / "config.json");
    out << config;
    if (!out) throw std::runtime_error((work / "config.json").string() + ": write failed");
  }
  if (fs::exists(result.folder)) fs::remove_all(result.folder);  // --force
  fs::rename(work, result.folder);
  return result;
}

}  // namespace salsa
