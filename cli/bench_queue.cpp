// salsa bench queue FILE: what `salsa run` of a queue costs, beside its bare-Box2D floor.
//
// Each test runs exactly as `salsa run` runs it (run_test: metrics, summary, drones.csv, targets.csv,
// into a scratch folder), while the commanded velocities are recorded; the same worker then replays
// them in a bare Box2D world (bench::Floor). Both sides run under the same number of workers, so they
// see the same contention, and the ratio is the sum of the runs' stepping time over the sum of the
// floors'. Set-up (map generation, target placement) is reported separately, as `bench table1` does.
#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>

#include "commands.hpp"
#include "salsa/core/run/bench.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/run/runner.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using namespace salsa;

namespace {

struct Timing {
  std::size_t drones = 0;
  double setup = 0, stepping = 0, floor = 0, simulated = 0;
};

/// A scratch folder for the runs' data, removed at the end whatever happens.
struct Scratch {
  fs::path path;
  Scratch() {
    std::string pattern = (fs::temp_directory_path() / "salsa-bench-queue-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("cannot create a scratch folder in " + fs::temp_directory_path().string());
    path = pattern;
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

int bench_queue(const po::variables_map& vm, const PluginHost& host, const std::string& cpu) {
  if (!vm.count("file")) throw InputError("bench queue: missing FILE (a queue or test file)");
  const fs::path file = vm["file"].as<std::string>();
  QueueOptions qo;
  qo.yes = true;  // a benchmark of a big queue is what the user asked for
  Queue queue = load_queue(file, host, qo);
  if (vm.count("time"))
    for (auto& t : queue.tests) {
      t.time = vm["time"].as<double>();
      std::erase_if(t.changes, [&](const Change& c) { return c.time > t.time; });  // never reached
    }
  const int jobs = vm["jobs"].as<int>() > 0 ? vm["jobs"].as<int>() : static_cast<int>(std::thread::hardware_concurrency());
  const bool floor = vm.count("floor");
  Scratch scratch;

  std::cout << "salsa " << salsa_version() << " bench queue " << file.string() << ": " << queue.tests.size() << " tests, "
            << jobs << " worker(s) on " << std::thread::hardware_concurrency() << " cores (" << cpu << "), 1 decide thread per test"
            << (floor ? ", with the Box2D floor" : "") << std::endl;

  std::vector<Timing> timings(queue.tests.size());
  std::mutex print;
  const auto start = std::chrono::steady_clock::now();
  tbb::task_arena arena(jobs);
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, queue.tests.size(), [&](std::size_t i) {
      const TestSpec& test = queue.tests[i];
      RunOptions options;
      options.out = scratch.path;
      options.threads = 1;  // one simulation per worker, as `salsa run --jobs` does
      std::optional<bench::Floor> recording;
      if (floor) {
        recording.emplace(test.drone_total(), test.steps());
        options.on_step = [&](const Simulation& sim) { recording->record(sim); };
      }
      const RunResult r = run_test(test, host, options);
      Timing& t = timings[i];
      t.drones = test.drone_total();
      t.simulated = test.time;
      t.stepping = r.stepping_seconds;
      t.setup = r.wall_seconds - r.stepping_seconds;
      if (recording) t.floor = recording->replay_seconds(make_setup(test, host, 1));
      std::error_code ec;
      fs::remove_all(r.folder, ec);
      std::lock_guard lock(print);
      std::cout << "  " << std::left << std::setw(40) << test.name << std::right << std::fixed << std::setprecision(2)
                << std::setw(8) << t.stepping << " s";
      if (floor) std::cout << "  floor " << std::setw(7) << t.floor << " s  ratio " << t.stepping / t.floor;
      std::cout << std::endl;
    }, tbb::simple_partitioner());
  });
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Per swarm size, then the whole queue.
  std::map<std::size_t, Timing> by_size;
  Timing all;
  for (const Timing& t : timings) {
    for (Timing* sum : {&by_size[t.drones], &all}) {
      sum->drones = t.drones;
      sum->setup += t.setup, sum->stepping += t.stepping, sum->floor += t.floor, sum->simulated += t.simulated;
    }
  }
  std::cout << "\n" << std::left << std::setw(8) << "drones" << std::right << std::setw(12) << "setup_s" << std::setw(12)
            << "stepping_s" << std::setw(12) << "RTF";
  if (floor) std::cout << std::setw(12) << "floor_s" << std::setw(8) << "ratio";
  std::cout << "\n";
  nlohmann::ordered_json report;
  report["workload"] = "queue";
  report["file"] = file.string();
  report["salsa"] = salsa_version();
  report["cores"] = std::thread::hardware_concurrency();
  report["cpu"] = cpu;
  report["jobs"] = jobs;
  report["tests"] = queue.tests.size();
  report["elapsed_s"] = elapsed;
  report["sizes"] = nlohmann::ordered_json::array();
  auto row = [&](const std::string& label, const Timing& t) {
    std::cout << std::left << std::setw(8) << label << std::right << std::fixed << std::setprecision(2) << std::setw(12) << t.setup
              << std::setw(12) << t.stepping << std::setprecision(5) << std::setw(12) << t.stepping / t.simulated;
    nlohmann::ordered_json j = {{"drones", label}, {"setup_s", t.setup}, {"stepping_s", t.stepping}, {"rtf", t.stepping / t.simulated}};
    if (floor) {
      std::cout << std::setprecision(2) << std::setw(12) << t.floor << std::setw(8) << t.stepping / t.floor;
      j["floor_s"] = t.floor;
      j["ratio_to_floor"] = t.stepping / t.floor;
    }
    std::cout << "\n";
    return j;
  };
  for (const auto& [size, t] : by_size) report["sizes"].push_back(row(std::to_string(size), t));
  report["all"] = row("all", all);
  std::cout << "queue wall time: " << std::setprecision(1) << elapsed << " s with " << jobs << " worker(s)"
            << " (set-up included; stepping and floor are summed over tests)\n";
  if (vm.count("json")) {
    std::ofstream out(vm["json"].as<std::string>());
    out << report.dump(2) << "\n";
    if (!out) throw std::runtime_error(vm["json"].as<std::string>() + ": cannot write");
  }
  return 0;
}
