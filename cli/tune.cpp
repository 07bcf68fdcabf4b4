// salsa tune FILE: tunes a test's parameters (docs/tuning.md). Every evaluation is an ordinary test run
// into OUT/<candidate>_<world>/ by the queue runner (--jobs, MPI ranks), so a tune has the provenance
// of any run, and --resume works as a queue's does: the tune is a deterministic function of its tests'
// results, so a resumed tune replays itself, finds the finished tests on disk, and runs only the rest.
#include <unistd.h>

#include <oneapi/tbb/info.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <vector>

#include "salsa/core/results/queue_summary.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "salsa/core/run/signals.hpp"
#include "salsa/plots/results.hpp"
#include "commands.hpp"
#include "mpi.hpp"
#include "options.hpp"
#include "queue_run.hpp"
#include "salsa/core/experiments/tune_file.hpp"
#include "tuner.hpp"

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using namespace salsa;
using namespace salsa::cli;

namespace {

po::options_description tune_options() {
  po::options_description o("tune options");
  o.add_options()("file", po::value<std::string>(), "the tune file")(
      "out,o", po::value<std::string>()->default_value("tune"), "output folder: one test folder per evaluation, tune.csv, best.json, report.txt, plots/")(
      "jobs,j", po::value<std::string>(), "tests run at once (default: all cores; 1 per rank under mpirun)")(
      "threads", po::value<std::string>()->default_value("0"), "threads for each simulation's decide phase (0: all cores; default 1 when tests run side by side)")(
      "time", po::value<std::string>(), "simulated seconds of every evaluation's test (overrides the tune's test, as salsa run --time)")(
      "evaluations", po::value<std::string>(), "the budget's evaluations (overrides the tune file's budget.evaluations)")(
      "resume", "continue an interrupted tune in OUT: finished tests are read back, the rest run")(
      "force", "replace what an earlier tune wrote in OUT")(
      "no-plots", "do not draw the tune's plots");
  return o;
}

/// --force over an earlier tune: what it wrote goes, so none of its evaluations (it may have had more)
/// outlive it. Only folders with salsa's marker, none holding other results, and the tune's own files.
void remove_earlier_tune(const fs::path& out) {
  std::vector<fs::path> tests;
  std::error_code ec;
  for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec))
    if (salsa_wrote(it->path())) tests.push_back(it->path());
  if (ec) throw WriteError(out.string() + ": cannot list the folder (" + ec.message() + ")");
  for (const fs::path& folder : tests)  // all checked before any goes
    if (const std::string why = nested_results(folder); !why.empty()) throw InputError(why);
  for (const fs::path& folder : tests) remove_ours(folder);
  for (const char* file : {"tune.csv", "candidates.csv", "best.json", "report.txt", "tune_plots.json", "summary.csv", "timing.csv", "front", "plots"}) {
    fs::remove_all(out / file, ec);  // its plots too: another tune's parameters have other plots
    if (ec) throw WriteError((out / file).string() + ": cannot remove (" + ec.message() + ")");
  }
}

/// "--time 30 --evaluations 20", or "neither --time nor --evaluations": a tune.json's "command_line".
std::string overrides_text(const json& line) {
  std::string out;
  for (const char* key : {"time", "evaluations"})
    if (line.contains(key)) out += (out.empty() ? "--" : " --") + std::string(key) + " " + line[key].dump();
  return out.empty() ? "neither --time nor --evaluations" : out;
}

/// OUT/tune.json records the tune file that writes OUT: another tune is refused, the same one needs --resume.
void claim_tune_folder(const fs::path& out, const TuneSpec& spec, bool resume, bool force) {
  const fs::path record = out / "tune.json";
  if (fs::exists(record) && !force) {
    std::ifstream in(record);
    std::stringstream text;
    text << in.rdbuf();
    if (text.str() != spec.canonical + "\n") {
      json recorded;
      try {
        recorded = json::parse(text.str());
      } catch (const json::exception&) {
      }
      // --time and --evaluations are part of the tune: resuming with others would mix two tunes.
      const json before = recorded.is_object() ? recorded.value("command_line", json::object()) : json::object();
      if (const json now = json::parse(spec.canonical).value("command_line", json::object()); before != now)
        throw InputError(out.string() + ": holds a tune run with " + overrides_text(before) + ", and this one has " + overrides_text(now) +
                         " (allowed: the same with --resume, or --force to start again, or another --out)");
      throw InputError(out.string() + ": holds another tune (its tune.json differs from " + spec.source +
                       "; allowed: the same tune file and seed with --resume, or --force to replace it, or another --out)");
    }
    if (!resume) throw InputError(out.string() + ": holds this tune already (allowed: --resume to continue it, --force to start again, or another --out)");
  } else if (!fs::exists(record) && holds_results(out)) {
    // A queue's folder: --force replaces only what a tune wrote.
    throw InputError(out.string() + ": holds the results of salsa run (no tune.json), which salsa tune never writes into, even with --force " +
                     "(allowed: another --out folder)");
  }
  if (force && holds_tune(out)) remove_earlier_tune(out);
  replace_file(record, spec.canonical + "\n");
}

}  // namespace


int cmd_tune(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "tune", "FILE [options]", tune_options(), vm, plugin_options | queue_options, positional("file", 1))) return 0;
  if (!vm.count("file")) throw InputError("tune: missing FILE (a tune file, see docs/tuning.md)");
  const bool quiet = vm.count("quiet");
  install_signal_handlers();
  const bool mpi = under_mpirun();
  if (mpi && !mpi_built())
    throw InputError("salsa runs under mpirun but was built without MPI: install libopenmpi-dev (Debian) and rebuild, or run without mpirun");
  if (vm.count("resume") && vm.count("force")) throw InputError("--resume and --force: one or the other");
  PluginHost host;
  load_plugins(host, vm, true);
  TuneOverrides overrides;
  if (vm.count("seed")) overrides.seed = queue_settings(vm).seed;
  // The ranges depend on the tune (its test's dt, its worlds): load_tune checks them.
  if (vm.count("time")) {
    const std::string text = vm["time"].as<std::string>();
    overrides.time = decimal(text);
    if (!overrides.time) throw InputError("--time: \"" + text + "\" is not a number (allowed: seconds, from the test's dt to 10000000)");
  }
  if (vm.count("evaluations")) {
    const std::string text = vm["evaluations"].as<std::string>();
    overrides.evaluations = decimal(text);
    if (!overrides.evaluations || *overrides.evaluations != std::floor(*overrides.evaluations))
      throw InputError("--evaluations: \"" + text + "\" is not a whole number (allowed: a whole number from the tune's tuning worlds to 1000000000)");
  }
  const TuneSpec spec = load_tune(vm["file"].as<std::string>(), host, overrides);

  RunOptions options;
  options.out = vm["out"].as<std::string>();
  options.force = vm.count("force");
  options.resume = !options.force;  // a test folder in OUT is this tune's (tune.json says so): read back, not rerun
  options.threads = static_cast<int>(whole_option(vm, "threads", 1024, "; 0 means all cores"));
  options.drones_csv = false;  // the largest file, and no objective reads it
  std::size_t jobs = vm.count("jobs") ? whole_option(vm, "jobs", 1024, "; 0 means all cores") : mpi ? 1 : 0;
  if (jobs == 0) jobs = static_cast<std::size_t>(std::max(1, tbb::info::default_concurrency()));
  if (jobs > 1 && vm["threads"].defaulted()) options.threads = 1;

  std::optional<MpiRun> world;
  if (mpi) world.emplace();
  const bool root = !world || world->rank() == 0;
  std::vector<std::string> command{"salsa"};
  command.insert(command.end(), argv, argv + argc);
  std::string line;
  for (const auto& a : command) line += (line.empty() ? "" : " ") + a;
  OutputLock lock;
  if (!claimed_on_rank0(world ? &*world : nullptr, [&] {
        lock = claim_output(options.out, 0, 1, line);
        claim_tune_folder(options.out, spec, vm.count("resume"), options.force);
      }))
    return 2;  // rank 0 said why

  QueueRunOptions queue;
  queue.jobs = jobs;
  queue.quiet = quiet || !root || !::isatty(STDOUT_FILENO);  // a terminal shows the bar; elsewhere one line per generation
  queue.plots = false;  // per-test plots of hundreds of evaluations: `salsa plot OUT/<test>` draws any of them
  queue.terminal = !world && ::isatty(STDOUT_FILENO);
  stop_may_exit(false);
  Tuner tuner(spec, host, options, queue, world ? &*world : nullptr, !quiet && root);
  try {
    const std::string why = tuner.tune();
    tuner.validate();
    if (!root) return 0;
    const bool draw = !vm.count("no-plots");
    if (draw) plots::start_plotting();
    const std::string text = tuner.finish(why, line, draw);
    if (!quiet) std::cout << text;
  } catch (const Stopped& s) {
    if (s.status >= 128 && root) std::cerr << "salsa: tune stopped; 'salsa tune " << spec.source << " --out " << options.out.string()
                                            << " --resume' continues it exactly" << std::endl;
    return s.status;
  }
  return 0;
}
