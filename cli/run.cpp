// salsa run FILE...: loads the tests, checks and locks the output folder, and runs the queue (all of
// it, a shard, an MPI rank's share, or one test of an --isolate run).
#include <sys/prctl.h>
#include <unistd.h>

#include <oneapi/tbb/info.h>

#include <algorithm>
#include <csignal>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "salsa/core/run/output_folder.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/results/queue_summary.hpp"
#include "salsa/core/experiments/shared_state.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "commands.hpp"
#include "isolate.hpp"
#include "mpi.hpp"
#include "options.hpp"
#include "queue_run.hpp"
#include "shard.hpp"

namespace fs = std::filesystem;
using namespace salsa;
using namespace salsa::cli;

namespace {

po::options_description run_options() {
  po::options_description o("run options");
  // Numbers are read as text and checked (options.hpp), so that "-1" or "1e400" get a one-line answer.
  o.add_options()("files", po::value<std::vector<std::string>>(), "test files")(
      "out,o", po::value<std::string>()->default_value("results"), "output folder; each test writes to OUT/<test name>/")(
      "time", po::value<std::string>(), "simulated seconds per test (overrides the files)")(
      "log-interval", po::value<std::string>(), "seconds between logged rows (overrides the files)")(
      "threads", po::value<std::string>()->default_value("0"), "threads for each simulation's decide phase (0: all cores; default 1 when tests run side by side)")(
      "no-drones-csv", "do not write drones.csv (it is the largest file)")(
      "archive", "also write trajectories.nc: the drones' positions, velocities, groups, status, energy and battery (and --drone-columns) at every logged step, compressed (netCDF-4)")(
      "drone-columns", po::value<std::string>(), "more columns of drones.csv and trajectories.nc: drone state columns by name, comma-separated, e.g. steering,air_velocity (salsa describe columns)")(
      "resume", "skip tests whose output folder holds the identical finished test")(
      "force", "replace the output folders salsa wrote for these tests")(
      "isolate", "run each test in its own process: a crashing plugin fails that test only")(
      "jobs,j", po::value<std::string>(), "tests run at once (default: all cores; 1 per rank under mpirun)")(
      "shard", po::value<std::string>(), "run only share i of n of the queue (test k when k % n == i), e.g. 0/4; default from a Slurm job array")(
      "no-plots", "do not draw the per-test and queue plots");
  return o;
}

/// The hidden option an --isolate run gives each test's process: run only the test of that name.
po::options_description child_options() {
  po::options_description o;
  o.add_options()("only", po::value<std::string>(), "");
  return o;
}


/// Loads every file's queue and applies the command-line overrides (with the same checks as the files).
std::vector<TestSpec> load_all(const po::variables_map& vm, const PluginHost& host, QueueRecord& comparison) {
  if (!vm.count("files")) throw InputError("missing FILE (a test file, see examples/)");
  const QueueOptions options = queue_settings(vm);
  std::vector<TestSpec> all;
  std::unordered_map<std::string, std::string> sources;  // name -> where it was given
  for (const auto& f : vm["files"].as<std::vector<std::string>>()) {
    Queue queue = load_queue(f, host, options);
    if (comparison.reference.empty() && comparison.top == 0)  // the first file's that has either
      comparison.reference = queue.reference, comparison.top = queue.top;
    for (auto& t : queue.tests) {
      if (vm.count("time")) {
        t.time = seconds_option(vm, "time", t);
        // Changes past the new end never apply; dropped, config.json stays a valid test.
        std::erase_if(t.changes, [&](const Change& c) { return c.time > t.time; });
      }
      if (vm.count("log-interval")) t.log_interval = seconds_option(vm, "log-interval", t);
      if (vm.count("archive")) t.archive = true;
      if (const auto [it, fresh] = sources.emplace(t.name, t.source); !fresh)
        throw InputError(t.source + ": name: \"" + t.name + "\" is already used by " + it->second);
      all.push_back(std::move(t));
    }
  }
  // load_queue refuses the same test twice within a file; across files it is the same mistake.
  std::vector<const TestSpec*> specs;
  specs.reserve(all.size());
  for (const TestSpec& t : all) specs.push_back(&t);
  if (const auto same = first_same_test(specs))
    throw InputError(all[same->second].source + ": the same test as " + all[same->first].source +
                     " (the same world, seed and behavior give the same data; give one a \"seed\", or use a queue's \"repeats\")");
  return all;
}


}  // namespace

int cmd_run(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "run", "FILE... [options]", run_options(), vm, plugin_options | queue_options, positional("files"), child_options())) return 0;
  const bool quiet = vm.count("quiet");
  const bool child = vm.count("only");  // one test of an --isolate run
  install_signal_handlers();
  if (child) ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // its run was killed: stop cleanly, not run on alone
  if (vm.count("isolate") && child) throw InputError("--isolate: not with --only");
  // Several ranks of mpirun: MPI hands out the tests (the child of an --isolate run is one test only).
  const bool mpi = !child && under_mpirun();
  if (mpi && !mpi_built())
    throw InputError("salsa runs under mpirun but was built without MPI: install libopenmpi-dev (Debian) and rebuild, or run without mpirun");
  if (mpi && vm.count("shard")) throw InputError("--shard: not under mpirun (MPI hands out the tests)");
  RunOptions options;
  options.out = vm["out"].as<std::string>();
  options.force = vm.count("force");
  options.resume = vm.count("resume");
  options.threads = static_cast<int>(whole_option(vm, "threads", 1024, "; 0 means all cores"));
  options.drones_csv = !vm.count("no-drones-csv");
  if (vm.count("drone-columns")) {
    if (!options.drones_csv && !vm.count("archive"))
      throw InputError("--drone-columns: not with --no-drones-csv unless --archive (they are columns of drones.csv and trajectories.nc)");
    std::stringstream list(vm["drone-columns"].as<std::string>());
    for (std::string name; std::getline(list, name, ',');) options.drone_columns.push_back(name);
    if (const std::string why = drone_columns_problem(options.drone_columns); !why.empty()) throw InputError("--drone-columns: " + why);
  }
  std::size_t jobs = vm.count("jobs") ? whole_option(vm, "jobs", 1024, "; 0 means all cores") : mpi ? 1 : 0;
  if (jobs == 0) jobs = static_cast<std::size_t>(std::max(1, tbb::info::default_concurrency()));
  const auto [shard, shards] = mpi || child ? std::pair<std::size_t, std::size_t>{0, 1} : shard_option(vm);
  PluginHost host;
  load_plugins(host, vm, !child);
  QueueRecord comparison;  // only its reference and top
  const auto tests = load_all(vm, host, comparison);
  // Every test valid before the first one runs; tests that will take hours are said so up front.
  for (const auto& t : tests) warn_workload(t, make_setup(t, host), quiet || child);
  // A comparison that mixes global knowledge with a radio's says so here, in queue.json and on its plots.
  const std::string sharing = child ? std::string() : shared_state_warning(tests, host);
  if (!sharing.empty() && !quiet) std::cerr << "salsa: warning: the queue " << sharing << "\n";
  // This process's share: one test (--isolate child), a shard (test k when k % n == i), or all.
  std::vector<std::size_t> mine;
  for (std::size_t k = 0; k < tests.size(); ++k)
    if (child ? tests[k].name == vm["only"].as<std::string>() : k % shards == shard) mine.push_back(k);
  if (child && mine.empty()) throw InputError("--only: no test named \"" + vm["only"].as<std::string>() + "\"");
  jobs = std::max<std::size_t>(1, std::min(jobs, mpi ? jobs : mine.size()));
  // Tests side by side each get one thread, unless --threads says otherwise: more would oversubscribe.
  if (jobs > 1 && vm["threads"].defaulted()) options.threads = 1;

  std::optional<MpiRun> world;
  if (mpi) world.emplace();
  const bool root = !world || world->rank() == 0;
  // The checks of the output folder: by rank 0 only under MPI (the others wait for its verdict). Rank 0
  // holds OUT's lock for the whole run (an --isolate child runs under its parent's).
  OutputLock lock;
  if (!claimed_on_rank0(world ? &*world : nullptr, [&] {
        std::vector<TestSpec> checked;
        for (std::size_t k : mine) checked.push_back(tests[k]);
        if (world) checked = tests;
        std::vector<std::string> command{"salsa"};
        command.insert(command.end(), argv, argv + argc);
        if (!child || !OutputLock::held_by_parent(options.out)) {
          std::string line;
          for (const auto& a : command) line += (line.empty() ? "" : " ") + a;
          lock = claim_output(options.out, shard, shards, line);
        }
        std::optional<QueueRecord> record;  // an --isolate child's run has recorded its queue already
        if (!child) {
          record = queue_record(tests, host, command);
          record->reference = comparison.reference, record->top = comparison.top;
          if (!sharing.empty()) record->warnings.push_back("the queue " + sharing);
          check_queue_folder(options.out, *record, options.resume, options.force);
        }
        check_outputs(checked, host, options);
        if (record) claim_queue_folder(options.out, *record, options.resume, options.force);
      }))
    return 2;  // rank 0 said why

  QueueRunOptions run;
  run.jobs = jobs;
  run.quiet = quiet || child;
  run.plots = !vm.count("no-plots") && !child;
  run.terminal = !world && ::isatty(STDOUT_FILENO);
  run.expected = world ? (root ? tests.size() : 0) : mine.size();
  // Every rank's children: rank 0 holds the lock for all of them.
  if (vm.count("isolate")) OutputLock::share_with_children(options.out);
  if (vm.count("isolate"))
    run.isolated = [&, threads = vm["threads"].defaulted() ? std::to_string(options.threads) : ""](const TestSpec& t) {
      return run_isolated(t, host, argc, argv, threads);
    };
  // From here a stop is the run's to handle: it ends the test that steps (the watchdog steps in only
  // while one does, a step may take minutes) and writes what it owes; --isolate's children stop themselves.
  stop_may_exit(false);
  std::unique_ptr<Dispatch> dispatch = world ? world->dispatch(tests.size()) : std::make_unique<ListDispatch>(mine);
  const QueueResult result = run_queue(tests, host, options, run, *dispatch);
  int status = result.status;
  if (child || result.write_failed) return status;  // a full disk: nothing more written
  if (world && root && world->others_failed() > 0 && status == 0) status = 1;
  if (status != 0 && status != 1) return status;  // stopped: the summary waits for the rest
  if (!root) return status;
  if (shards > 1) {
    if (!quiet)
      std::cout << "shard " << shard << "/" << shards << " done; once every shard is done, 'salsa summarize " << options.out.string()
                << "' writes the queue summary" << std::endl;
    return status;
  }
  finish_queue(options.out, host, run.plots);
  if (!quiet) std::cout << "results in " << options.out.string() << std::endl;
  return status;
}

