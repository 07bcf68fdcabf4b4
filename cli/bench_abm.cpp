// salsa bench abm-flocking: the ABM frameworks' flocking model (JuliaDynamics/ABMFrameworksComparison,
// Flocking) as they run it, both sizes, 100 steps, many seeds, beside their published figures.
#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "commands.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/files/input_error.hpp"
#include "salsa/core/run/bench.hpp"

namespace po = boost::program_options;
using namespace salsa;

namespace {

/// The frameworks' own figures for their flocking model, agent-steps per second per core: measured
/// elsewhere (other hardware), quoted beside salsa's so a reader sees the scale, never compared as a
/// ratio. Source: JuliaDynamics/ABMFrameworksComparison (Flocking), read 2026-11-29.
struct Published {
  const char* framework;
  double small;  ///< agent-steps/s/core on the small model; 0: not published
};
constexpr Published published[] = {{"Agents.jl", 2.0e6}, {"Ark.jl", 2.7e6}, {"Mesa", 1.3e4}};

/// salsa bench abm-flocking: both sizes of the frameworks' flocking model, 100 steps from seeds 1..N,
/// timed by this process's CPU clock on one thread (their figures are per core).
}  // namespace

int bench_abm_flocking(const po::variables_map& vm, const PluginHost& host, const std::string& cpu) {
  const int seeds = vm.count("seeds") ? vm["seeds"].as<int>() : 100;
  if (seeds < 1 || seeds > 1000) throw InputError("--seeds: " + std::to_string(seeds) + " is out of range (allowed: 1 to 1000)");
  try {
    host.behavior("abm_flocking");
  } catch (const UnknownPlugin& e) {
    throw InputError(std::string("bench abm-flocking: ") + e.what());
  }
  constexpr std::size_t steps = 100;  // the declaration's
  std::cout << "salsa " << salsa_version() << " bench abm-flocking: " << cpu << ", 1 thread, CPU clock, " << steps
            << " steps per run, seeds 1.." << seeds << ", light physics\n";
  std::cout << std::left << std::setw(8) << "model" << std::right << std::setw(8) << "birds" << std::setw(10) << "cpu_s"
            << std::setw(22) << "agent-steps/s/core" << std::setw(12) << "median_ms" << std::endl;
  nlohmann::ordered_json report;
  report["workload"] = "abm-flocking";
  report["salsa"] = salsa_version();
  report["cpu"] = cpu;
  report["threads"] = 1;
  report["clock"] = "process CPU";
  report["steps"] = steps;
  report["seeds"] = seeds;
  report["models"] = nlohmann::ordered_json::array();
  for (const bool large : {false, true}) {
    std::vector<double> runs;
    std::size_t birds = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
      SimulationSetup setup = bench::abm_flocking(host, large, static_cast<std::uint64_t>(seed));
      birds = setup.groups.front().drones;
      Simulation sim(setup);
      const double start = bench::seconds_now(true);
      sim.run_steps(steps);
      runs.push_back(bench::seconds_now(true) - start);
    }
    double total = 0;
    for (double r : runs) total += r;
    std::sort(runs.begin(), runs.end());
    const double median = runs[runs.size() / 2];
    const double rate = static_cast<double>(birds * steps) * seeds / total;
    const char* name = large ? "large" : "small";
    std::cout << std::left << std::setw(8) << name << std::right << std::setw(8) << birds << std::fixed << std::setprecision(3)
              << std::setw(10) << total << std::scientific << std::setprecision(2) << std::setw(22) << rate << std::fixed
              << std::setprecision(3) << std::setw(12) << median * 1e3 << std::endl;
    report["models"].push_back({{"model", name}, {"birds", birds}, {"cpu_s", total}, {"agent_steps_per_s", rate}, {"median_run_s", median}});
  }
  std::cout << "published, measured elsewhere (JuliaDynamics/ABMFrameworksComparison, read 2026-11-29), small model:";
  report["published_elsewhere"] = nlohmann::ordered_json::object();
  for (const Published& p : published) {
    std::cout << " " << p.framework << " " << std::scientific << std::setprecision(1) << p.small;
    report["published_elsewhere"][p.framework] = {{"small_agent_steps_per_s", p.small}};
  }
  std::cout << " agent-steps/s/core" << std::endl;
  if (vm.count("json")) {
    std::ofstream out(vm["json"].as<std::string>());
    out << report.dump(2) << "\n";
    if (!out) throw std::runtime_error(vm["json"].as<std::string>() + ": cannot write");
  }
  return 0;
}

