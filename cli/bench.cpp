// salsa bench: whole-workload speed figures (workloads: docs/benchmarks.md), beside the Box2D floor.
#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <thread>

#include <oneapi/tbb/info.h>

#include "commands.hpp"
#include "options.hpp"
#include "salsa/core/run/bench.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace po = boost::program_options;
using namespace salsa;

namespace {

struct Cell {
  std::size_t drones, targets;
};

struct Stats {
  double mean = 0, min = 0, max = 0;
};
Stats stats(const std::vector<double>& v) {
  Stats s{0, *std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end())};
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  return s;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

std::vector<Cell> parse_cells(const std::string& text) {
  std::vector<Cell> cells;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    const auto x = item.find('x');
    try {
      if (x == std::string::npos) throw std::invalid_argument(item);
      cells.push_back({std::stoul(item.substr(0, x)), std::stoul(item.substr(x + 1))});
      if (cells.back().drones == 0 || cells.back().drones > 1'000'000 || cells.back().targets > 10'000'000)
        throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError("--cells: '" + item + "' is not DRONESxTARGETS (allowed: 1..1000000 drones, 0..10000000 targets, e.g. 100x1000)");
    }
  }
  return cells;
}

}  // namespace

int cmd_bench(int argc, char** argv) {
  po::options_description o("bench options");
  o.add_options()("workload", po::value<std::string>(), "table1, scale, queue or abm-flocking")(
      "file", po::value<std::string>(), "queue: the queue or test file to time")(
      "jobs", po::value<int>()->default_value(0), "queue: tests run at once (0: all cores)")(
      "cells", po::value<std::string>(), "table1 cells DRONESxTARGETS, comma-separated (default: the 12 cells of Table I)")(
      "behavior", po::value<std::string>()->default_value("flocking"), "table1: the behavior (flocking with the paper's parameters, others with their defaults)")(
      "sizes", po::value<std::string>()->default_value("1000,10000,100000"), "scale: drone counts")(
      "seeds", po::value<int>(), "seeds 1..N per cell (default: 5 for table1, 1 for scale, 100 for abm-flocking)")(
      "threads", po::value<int>()->default_value(0), "decide threads (0: all cores)")(
      "time", po::value<double>(), "simulated seconds per run (default: 100 for table1, 10 for scale)")(
      "decision-lag", po::value<int>(),
      "0 (default, as in test files): all phases in sequence, table1's definition; 1: Box2D overlaps sensing and deciding")(
      "physics", po::value<std::string>()->default_value("box2d"), "box2d, or light: salsa's own parallel physics (docs/architecture.md)")(
      "floor", "also time the bare-Box2D floor of each cell and print the ratio")(
      "cpu-time", "time runs and floor by this process's CPU clock, not the wall clock (with --threads 1 on a busy machine)")(
      "profile", "print the time spent in each step phase")(
      "fleet", "table1: two groups of half the swarm, batteries and failure rates on (the fleet model's cost)")(
      "wind", "table1: a 3 m/s wind with gusts of 1 m/s (the wind model's cost)")(
      "pile", "the swarm, half of it twice the radius, starts packed around the spawn point and flies into it (the physics' densest work)")("comm", po::value<double>(), "table1: every drone broadcasts its position and velocity every step to drones within RANGE m, line of sight on (the comm model's cost)")("json", po::value<std::string>(), "write all figures to this JSON file");
  po::positional_options_description pos;
  pos.add("workload", 1).add("file", 1);
  po::variables_map vm;
  if (!cli::parse(argc, argv, "bench", "table1|scale [options]\n       salsa bench queue FILE [--jobs N] [--floor] [--json F]\n       salsa bench abm-flocking [--seeds N] [--json F]", o, vm,
                  cli::plugin_options, pos))
    return 0;
  if (!vm.count("workload")) throw InputError("bench: missing WORKLOAD (allowed: table1, scale, queue, abm-flocking; see 'salsa bench --help')");
  const std::string workload = vm["workload"].as<std::string>();
  if (workload != "table1" && workload != "scale" && workload != "queue" && workload != "abm-flocking")
    throw InputError("bench: unknown workload '" + workload + "' (allowed: table1, scale, queue, abm-flocking)");
  if (vm["jobs"].as<int>() < 0 || vm["jobs"].as<int>() > 1024)
    throw InputError("--jobs: " + std::to_string(vm["jobs"].as<int>()) + " is out of range (allowed: 0 to 1024; 0 means all cores)");
  if (vm.count("time") && !(vm["time"].as<double>() >= 1.0 / 60 && vm["time"].as<double>() <= 1e7))
    throw InputError("--time: out of range (allowed: 1/60 to 10000000 s)");
  // Options another workload reads are refused, not silently ignored.
  auto only = [&](std::initializer_list<const char*> allowed) {
    for (const auto& [name, value] : vm) {
      if (value.defaulted() || name == "workload" || name == "plugin-dir" || name == "quiet") continue;
      if (std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return name == a; }) != allowed.end()) continue;
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + "--" + a;
      throw InputError("bench " + workload + ": --" + name + " does not apply to this workload (allowed: " + list + ", --plugin-dir)");
    }
  };
  if (workload == "queue") {
    only({"file", "jobs", "time", "floor", "json"});
    PluginHost host;
    host.load(PluginHost::default_search_path(cli::plugin_dirs(vm)));
    return bench_queue(vm, host, cpu_model());
  }
  if (workload == "abm-flocking") {
    only({"seeds", "json"});
    PluginHost host;
    host.load(PluginHost::default_search_path(cli::plugin_dirs(vm)));
    return bench_abm_flocking(vm, host, cpu_model());
  }
  const bool is_table1 = workload == "table1";
  if (is_table1)
    only({"cells", "behavior", "seeds", "threads", "time", "decision-lag", "physics", "floor", "cpu-time", "profile", "fleet", "wind", "pile", "comm", "json"});
  else
    only({"sizes", "behavior", "seeds", "threads", "time", "decision-lag", "physics", "floor", "cpu-time", "profile", "fleet", "wind", "pile", "comm", "json"});
  const int threads = vm["threads"].as<int>();
  if (threads < 0 || threads > 1024) throw InputError("--threads: " + std::to_string(threads) + " is out of range (allowed: 0 to 1024)");
  const int seeds = vm.count("seeds") ? vm["seeds"].as<int>() : (is_table1 ? 5 : 1);
  if (seeds < 1 || seeds > 1000) throw InputError("--seeds: " + std::to_string(seeds) + " is out of range (allowed: 1 to 1000)");
  const double sim_time = vm.count("time") ? vm["time"].as<double>() : (is_table1 ? 100.0 : 10.0);
  if (!(sim_time >= 1.0 / 60 && sim_time <= 1e5)) throw InputError("--time: out of range (allowed: 1/60 to 100000 s)");
  const bool floor = vm.count("floor"), profile = vm.count("profile"), cpu = vm.count("cpu-time");
  // The default everywhere (test files, the desktop, both workloads): no lag, the paper's definition.
  const int lag = vm.count("decision-lag") ? vm["decision-lag"].as<int>() : 0;
  if (lag != 0 && lag != 1) throw InputError("--decision-lag: " + std::to_string(lag) + " is out of range (allowed: 0 or 1)");
  const std::string physics = vm["physics"].as<std::string>();
  if (physics != "box2d" && physics != "light") throw InputError("--physics: '" + physics + "' is not a physics (allowed: box2d, light)");
  const double comm_range = vm.count("comm") ? vm["comm"].as<double>() : 0;
  if (vm.count("comm") && !(comm_range >= 1e-3 && comm_range <= 1e6))
    throw InputError("--comm: " + Parameter::format(comm_range) + " is out of range (allowed: a range in [0.001, 1000000] m)");

  std::vector<Cell> cells;
  if (!is_table1) {
    for (const Cell& c : parse_cells([&] {
           std::string s = vm["sizes"].as<std::string>(), out;
           std::stringstream in(s);
           for (std::string n; std::getline(in, n, ',');) out += (out.empty() ? "" : ",") + n + "x0";
           return out;
         }()))
      cells.push_back({c.drones, 10 * c.drones});
  } else if (vm.count("cells")) {
    cells = parse_cells(vm["cells"].as<std::string>());
  } else {
    for (std::size_t n : {10, 100, 500, 1000})
      for (std::size_t m : {100, 1000, 10000}) cells.push_back({n, m});
  }

  PluginHost host;
  host.load(PluginHost::default_search_path(cli::plugin_dirs(vm)));
  const std::string behavior = vm["behavior"].as<std::string>();
  try {
    host.behavior(behavior);
  } catch (const UnknownPlugin& e) {
    throw InputError(std::string("--behavior: ") + e.what());
  }

  const int used_threads = threads > 0 ? threads : tbb::info::default_concurrency();
  std::cout << "salsa " << salsa_version() << " bench " << workload << ": " << std::thread::hardware_concurrency()
            << " cores (" << cpu_model() << "), " << used_threads << " decide thread(s), " << sim_time
            << " s simulated per run, seeds 1.." << seeds << ", decision lag " << lag << (cpu ? ", CPU clock" : "")
            << (comm_range > 0 ? ", comm range " + Parameter::format(comm_range) + " m" : "")
            << (physics == "light" ? ", light physics" : "") << (vm.count("pile") ? ", a pile" : "") << "\n";
  std::cout << std::left << std::setw(8) << "drones" << std::setw(9) << "targets" << std::right << std::setw(9) << "setup_s"
            << std::setw(9) << "wall_s" << std::setw(10) << "RTF" << std::setw(22) << "RTF min-max" << std::setw(13)
            << "steps/s" << std::setw(15) << "drone-steps/s" << std::setw(9) << "peak_MB" << std::setw(10) << "found";
  if (floor) std::cout << std::setw(11) << "floor_RTF" << std::setw(8) << "ratio";
  std::cout << std::endl;

  nlohmann::ordered_json report;
  report["workload"] = workload;
  report["salsa"] = salsa_version();
  report["cores"] = std::thread::hardware_concurrency();
  report["cpu"] = cpu_model();
  report["threads"] = used_threads;
  report["simulated_s"] = sim_time;
  report["seeds"] = seeds;
  report["decision_lag"] = lag;
  report["clock"] = cpu ? "process CPU" : "wall";
  if (comm_range > 0) report["comm_range"] = comm_range;
  report["physics"] = physics;
  if (vm.count("pile")) report["pile"] = true;
  report["cells"] = nlohmann::ordered_json::array();

  const std::size_t steps = static_cast<std::size_t>(std::llround(sim_time * 60));
  for (const Cell& cell : cells) {
    std::vector<double> walls, setups, floors, found;
    std::array<double, phase_names.size()> phases{};
    std::size_t peak = 0;
    for (int seed = 1; seed <= seeds; ++seed) try {
      bench::Workload w = is_table1 ? bench::Workload{} : bench::scale(cell.drones, 0, 0);
      w.drones = cell.drones;
      w.targets = cell.targets;
      w.seed = static_cast<std::uint64_t>(seed);
      w.threads = threads;
      w.behavior = behavior;
      w.fleet = vm.count("fleet") > 0;
      w.wind = vm.count("wind") > 0;
      w.comm_range = comm_range;
      w.pile = vm.count("pile") > 0;
      w.physics = physics == "light" ? PhysicsMode::light : PhysicsMode::box2d;
      bench::reset_peak_rss();
      const auto t0 = std::chrono::steady_clock::now();
      SimulationSetup setup = bench::table1(host, w);
      setup.decision_lag = lag;
      setup.profile = profile;
      Simulation sim(setup);
      std::optional<bench::Floor> recording;
      if (floor) recording.emplace(cell.drones, steps);
      const auto t1 = std::chrono::steady_clock::now();
      const double run_start = bench::seconds_now(cpu);
      if (recording)
        for (std::size_t k = 0; k < steps; ++k) sim.step(), recording->record(sim);  // ~1 µs per 1,000 drones
      else
        sim.run_steps(steps);
      const double run_end = bench::seconds_now(cpu);
      setups.push_back(std::chrono::duration<double>(t1 - t0).count());
      walls.push_back(run_end - run_start);
      found.push_back(static_cast<double>(sim.targets_found()));
      for (std::size_t k = 0; k < phases.size(); ++k) phases[k] += sim.profile()[k];
      // The floor's recording is not salsa's memory.
      peak = std::max(peak, bench::peak_rss_bytes() - (recording ? recording->bytes() : 0));
      if (recording) floors.push_back(recording->replay_seconds(setup, cpu));
    } catch (const PluginFailure& e) {  // only the behavior is the user's choice: name it, the others by kind
      const std::string plugin = e.kind == "behavior" ? "behavior '" + behavior + "' (" + host.behavior(behavior).plugin().file.string() + ")"
                                                      : e.kind;
      throw std::runtime_error("bench " + workload + " (" + std::to_string(cell.drones) + " drones, seed " + std::to_string(seed) +
                               "): " + plugin + " failed: " + e.what());
    }
    const Stats wall = stats(walls), setup_s = stats(setups), found_s = stats(found);
    const double rtf = wall.mean / sim_time;
    const double drone_steps = static_cast<double>(cell.drones) * static_cast<double>(steps) / wall.mean;
    std::ostringstream range;
    range << std::fixed << std::setprecision(4) << wall.min / sim_time << "-" << wall.max / sim_time;
    std::cout << std::left << std::setw(8) << cell.drones << std::setw(9) << cell.targets << std::right << std::fixed
              << std::setprecision(3) << std::setw(9) << setup_s.mean << std::setw(9) << wall.mean << std::setprecision(4)
              << std::setw(10) << rtf << std::setw(22) << range.str() << std::setprecision(0) << std::setw(13)
              << static_cast<double>(steps) / wall.mean << std::setw(15) << drone_steps << std::setw(9)
              << static_cast<double>(peak) / 1e6 << std::setprecision(1) << std::setw(10) << found_s.mean;
    nlohmann::ordered_json j = {{"drones", cell.drones},
                                {"targets", cell.targets},
                                {"setup_s", setup_s.mean},
                                {"wall_s", wall.mean},
                                {"rtf", rtf},
                                {"rtf_min", wall.min / sim_time},
                                {"rtf_max", wall.max / sim_time},
                                {"drone_steps_per_s", drone_steps},
                                {"peak_bytes", peak},
                                {"targets_found", found_s.mean}};
    if (floor) {
      const double floor_rtf = stats(floors).mean / sim_time;
      std::cout << std::setprecision(4) << std::setw(11) << floor_rtf << std::setprecision(2) << std::setw(8) << rtf / floor_rtf;
      j["floor_rtf"] = floor_rtf;
      j["ratio_to_floor"] = rtf / floor_rtf;
    }
    std::cout << std::endl;
    nlohmann::ordered_json phase_json;
    if (profile) std::cout << "    ms/step:";
    for (std::size_t k = 0; k < phases.size(); ++k) {
      const double ms = phases[k] / seeds / static_cast<double>(steps) * 1e3;
      phase_json[phase_names[k]] = ms;
      if (profile) std::cout << " " << phase_names[k] << " " << std::setprecision(4) << ms;
    }
    if (profile) std::cout << std::endl;
    if (profile) j["phase_ms_per_step"] = phase_json;
    report["cells"].push_back(j);
  }
  if (vm.count("json")) {
    std::ofstream out(vm["json"].as<std::string>());
    out << report.dump(2) << "\n";
    if (!out) throw std::runtime_error(vm["json"].as<std::string>() + ": cannot write");
  }
  return 0;
}
