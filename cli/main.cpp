// salsa: the headless front-end. Thin: parses the command line and calls libsalsa.
#include <boost/program_options.hpp>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <algorithm>
#include <charconv>
#include <csignal>
#include <cstring>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <optional>
#include <unordered_map>
#include <sstream>

#include <oneapi/tbb/info.h>

#include "salsa/core/plugin_host.hpp"
#include "salsa/core/queue.hpp"
#include "salsa/core/queue_summary.hpp"
#include "salsa/core/runner.hpp"
#include "salsa/core/test_spec.hpp"
#include "commands.hpp"
#include "mpi.hpp"
#include "queue_run.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using namespace salsa;

namespace {

const char* usage = R"(usage: salsa <command> [options]

commands:
  run FILE...        run tests (a test, a list of tests, or a queue with a sweep) and write their data
  summarize OUT      write OUT/summary.csv (one row per test), comparison and plots from a queue's output folder
  validate FILE...   check test, queue and map files without running them
  queue expand FILE  print the tests a queue expands to (count, then one line each)
  plugins            list the plugins found, the folders searched and the files refused
  describe NAME      print a plugin's parameters (name, default, min, max, unit, meaning)
  bench WORKLOAD     measure speed (table1, scale)
  plot FOLDER|FILE   redraw the plots of a results or test folder; chart a bench JSON or summary.csv
  new-plugin KIND NAME  write NAME/: a plugin (behavior, target, map, contact-handler, metric), its test and CMakeLists.txt

'salsa <command> --help' shows the options of a command.
)";

po::options_description common_options() {
  po::options_description o("common options");
  o.add_options()("help,h", "show this help")(
      "plugin-dir", po::value<std::vector<std::string>>()->composing(), "also search this folder for plugins (repeatable, searched first)")(
      "quiet,q", "print only errors");
  return o;
}

/// Parses a subcommand's arguments; returns false when --help was printed. `hidden` options are
/// accepted but not shown in --help.
bool parse(int argc, char** argv, const std::string& command, const std::string& synopsis,
           po::options_description options, po::variables_map& vm, const char* positional = nullptr,
           const po::options_description& hidden = po::options_description()) {
  options.add(common_options());
  po::options_description all;
  all.add(options).add(hidden);
  po::positional_options_description pos;
  if (positional) pos.add(positional, -1);
  po::store(po::command_line_parser(argc, argv).options(all).positional(pos).run(), vm);
  po::notify(vm);
  if (vm.count("help")) {
    std::cout << "usage: salsa " << command << " " << synopsis << "\n\n" << options;
    return false;
  }
  return true;
}

std::vector<fs::path> plugin_dirs(const po::variables_map& vm) {
  std::vector<fs::path> dirs;
  if (vm.count("plugin-dir"))
    for (const auto& d : vm["plugin-dir"].as<std::vector<std::string>>()) dirs.emplace_back(d);
  return dirs;
}

void load_plugins(PluginHost& host, const po::variables_map& vm, bool report_failures) {
  host.load(PluginHost::default_search_path(plugin_dirs(vm)));
  if (report_failures && !vm.count("quiet"))
    for (const auto& f : host.failures())  // a whole file skipped, or one registration of a file that loaded
      std::cerr << "salsa: warning: plugin " << f.file.string() << (f.registration.empty() ? " skipped: " : ": ") << f.reason
                << "\n";
}

/// Says so on stderr when a test will likely take hours (estimated neighbours per drone and steps).
void warn_workload(const TestSpec& test, const SimulationSetup& setup, bool quiet) {
  if (quiet) return;
  if (const std::string line = workload_warning(test, setup); !line.empty()) std::cerr << "salsa: warning: " << line << "\n";
}

int cmd_plugins(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "plugins", "[options]", po::options_description("plugins options"), vm)) return 0;
  PluginHost host;
  load_plugins(host, vm, false);
  std::cout << "Folders searched, in order:\n";
  std::error_code ec;  // a link loop is "missing" here; the Refused list below says why
  for (const auto& d : host.searched())
    std::cout << "  " << std::left << std::setw(18) << d.origin << " " << d.path.string()
              << (fs::is_directory(d.path, ec) ? "" : "  (missing)") << "\n";
  // Columns as wide as their longest entry.
  std::vector<std::array<std::string, 5>> rows{{"KIND", "NAME", "VERSION", "BRIEF", "FILE"}};
  auto add = [&](const char* kind, const auto& entries) {
    for (const auto& e : entries)
      rows.push_back({kind, e.factory.name, e.plugin().version, e.factory.brief, e.plugin().file.string()});
  };
  add("behavior", host.behaviors());
  add("target", host.target_kinds());
  add("map", host.maps());
  add("contact handler", host.contact_handlers());
  add("metric", host.metrics());
  std::array<std::size_t, 5> width{};
  for (const auto& r : rows)
    for (std::size_t c = 0; c < r.size(); ++c) width[c] = std::max(width[c], r[c].size());
  std::cout << "\nPlugins:\n";
  for (const auto& r : rows) {
    std::cout << " ";
    for (std::size_t c = 0; c < r.size(); ++c) std::cout << " " << std::left << std::setw(c + 1 < r.size() ? int(width[c]) : 0) << r[c];
    std::cout << "\n";
  }
  if (!host.failures().empty()) {
    std::cout << "\nRefused:\n";
    for (const auto& f : host.failures()) std::cout << "  " << f.file.string() << ": " << f.reason << "\n";
  }
  return 0;
}

/// A metric's columns with its default parameters (they may depend on the parameters).
void describe_columns(const Entry<Metric>& e) {
  std::shared_ptr<Metric> metric;
  std::vector<Column> step, final;
  try {
    metric = PluginHost::create(e, ParameterValues(e.factory.parameters));
    step = metric->step_columns();
    final = metric->final_columns();
  } catch (const std::exception& x) {
    std::cout << "  columns cannot be listed: " << x.what() << "\n\n";
    return;
  }
  std::cout << "  " << std::left << std::setw(28) << "COLUMN" << std::setw(20) << "FILE" << std::setw(8) << "UNIT" << "MEANING\n";
  for (auto [file, columns] : {std::pair{"summary.csv", &step}, {"outcome.csv", &final}})
    for (const Column& c : *columns)
      std::cout << "  " << std::setw(28) << c.name << std::setw(20) << file << std::setw(8) << (c.unit.empty() ? "-" : c.unit)
                << c.meaning << "\n";
  std::cout << "\n";
}

int cmd_describe(int argc, char** argv) {
  po::options_description o("describe options");
  o.add_options()("name", po::value<std::string>(), "plugin name (behavior, target kind, map, contact handler or metric)");
  po::variables_map vm;
  if (!parse(argc, argv, "describe", "NAME [options]", o, vm, "name")) return 0;
  if (!vm.count("name")) throw InputError("describe: missing NAME (see 'salsa plugins' for the names)");
  const std::string name = vm["name"].as<std::string>();
  PluginHost host;
  load_plugins(host, vm, true);
  bool found = false;
  auto describe = [&](const char* kind, const auto& entries) {
    for (const auto& e : entries) {
      if (e.factory.name != name) continue;
      found = true;
      std::cout << kind << " '" << name << "': " << e.factory.brief << "\n  from " << e.plugin().file.string()
                << " (plugin " << e.plugin().name << " " << e.plugin().version << ")\n\n";
      if constexpr (std::is_same_v<std::decay_t<decltype(e)>, Entry<Metric>>) describe_columns(e);
      if (e.factory.parameters.empty()) {
        std::cout << "  no parameters\n";
        continue;
      }
      std::cout << "  " << std::left << std::setw(28) << "PARAMETER" << std::setw(10) << "DEFAULT" << std::setw(10) << "MIN"
                << std::setw(10) << "MAX" << std::setw(8) << "UNIT" << "MEANING\n";
      for (const auto& p : e.factory.parameters)
        std::cout << "  " << std::setw(28) << p.name << std::setw(10) << Parameter::format(p.value) << std::setw(10)
                  << Parameter::format(p.min) << std::setw(10) << Parameter::format(p.max) << std::setw(8)
                  << (p.unit.empty() ? "-" : p.unit) << p.description << (p.is_integer() ? " (whole number)" : "") << "\n";
    }
  };
  describe("behavior", host.behaviors());
  describe("target kind", host.target_kinds());
  describe("map", host.maps());
  describe("contact handler", host.contact_handlers());
  describe("metric", host.metrics());
  if (!found) throw InputError("describe: no plugin named '" + name + "' (see 'salsa plugins')");
  return 0;
}

po::options_description run_options() {
  po::options_description o("run options");
  // Numbers are read as text and checked here, so that "-1" or "1e400" get a one-line answer naming
  // what is allowed rather than wrapping around or a parser's message.
  o.add_options()("files", po::value<std::vector<std::string>>(), "test files")(
      "out,o", po::value<std::string>()->default_value("results"), "output folder; each test writes to OUT/<test name>/")(
      "seed", po::value<std::string>(), "queue seed of every file, a whole number in [0, 2^53]: each test's seed is paired from it (over the seeds in the files)")(
      "yes,y", "allow a queue of more than 10,000 tests")(
      "time", po::value<std::string>(), "simulated seconds per test (overrides the files)")(
      "log-interval", po::value<std::string>(), "seconds between logged rows (overrides the files)")(
      "threads", po::value<std::string>()->default_value("0"), "threads for each simulation's decide phase (0: all cores; default 1 when tests run side by side)")(
      "no-drones-csv", "do not write drones.csv (it is the largest file)")(
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

constexpr double max_seed = 9007199254740992.0;  // 2^53: what JSON numbers hold exactly

/// A decimal number given on the command line, or nullopt when the text is not one.
std::optional<double> decimal(const std::string& text) {
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec == std::errc::invalid_argument || end != text.data() + text.size()) return std::nullopt;
  return ec == std::errc::result_out_of_range ? HUGE_VAL : v;  // "1e400": out of range, not "not a number"
}

/// A whole number in [0, hi] given on the command line, or InputError naming the option.
std::uint64_t whole_option(const po::variables_map& vm, const char* name, std::uint64_t hi, const std::string& note = "") {
  const std::string text = vm[name].as<std::string>();
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  const std::string allowed = " (allowed: a whole number in [0, " + std::to_string(hi) + "]" + note + ")";
  if (text.empty() || ec == std::errc::invalid_argument || end != text.data() + text.size())
    throw InputError(std::string("--") + name + ": \"" + text + "\" is not a whole number" + allowed);
  if (ec == std::errc::result_out_of_range || v > hi) throw InputError(std::string("--") + name + ": " + text + " is out of range" + allowed);
  return v;
}

/// --time / --log-interval: a number of seconds in [dt, 1e7] of each test.
double seconds_option(const po::variables_map& vm, const char* name, const TestSpec& t) {
  const std::string text = vm[name].as<std::string>();
  const std::string allowed = " (allowed: [" + Parameter::format(t.dt) + ", 10000000] s for " + t.source + ")";
  const auto v = decimal(text);
  if (!v) throw InputError(std::string("--") + name + ": \"" + text + "\" is not a number" + allowed);
  if (!(*v >= t.dt && *v <= 1e7)) throw InputError(std::string("--") + name + ": " + text + " is out of range" + allowed);
  return *v;
}

/// --seed and --yes as QueueOptions.
QueueOptions queue_options(const po::variables_map& vm) {
  QueueOptions o;
  if (vm.count("seed")) o.seed = whole_option(vm, "seed", static_cast<std::uint64_t>(max_seed));
  o.yes = vm.count("yes");
  return o;
}

/// Loads every file's queue and applies the command-line overrides (with the same checks as the files).
std::vector<TestSpec> load_all(const po::variables_map& vm, const PluginHost& host) {
  if (!vm.count("files")) throw InputError("missing FILE (a test file, see examples/)");
  const QueueOptions options = queue_options(vm);
  std::vector<TestSpec> all;
  std::unordered_map<std::string, std::string> sources;  // name -> where it was given
  for (const auto& f : vm["files"].as<std::vector<std::string>>()) {
    for (auto& t : load_queue(f, host, options).tests) {
      if (vm.count("time")) {
        t.time = seconds_option(vm, "time", t);
        // Changes past the new end never apply; dropped, config.json stays a valid test.
        std::erase_if(t.changes, [&](const Change& c) { return c.time > t.time; });
      }
      if (vm.count("log-interval")) t.log_interval = seconds_option(vm, "log-interval", t);
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

/// --isolate: runs one test in a new process (this executable, the same arguments, --only NAME and
/// the decide threads `threads` when not "", as this run decided them) and waits for it, passing
/// SIGINT/SIGTERM on. Returns its wait status and what it wrote on stderr (the
/// caller prints it); a child that dies without a word gets a line of ours.
std::pair<int, std::string> run_isolated(const TestSpec& test, const PluginHost& host, int argc, char** argv,
                                         const std::string& threads) {
  std::vector<std::string> args{"salsa", "run"};
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) != "--isolate") args.emplace_back(argv[i]);
  args.insert(args.end(), {"--only", test.name});
  if (!threads.empty()) args.insert(args.end(), {"--threads", threads});
  std::vector<char*> cargs;
  for (auto& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
  // Its own process group: Ctrl-C reaches this process only, which passes it on once (a second
  // SIGINT would end the child at once instead of stopping it cleanly).
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, "/proc/self/exe", &actions, &attributes, cargs.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(pipe_fds[1]);
  if (spawned != 0) {
    ::close(pipe_fds[0]);
    throw TestFailure("test '" + test.name + "': cannot start its process (" + std::strerror(spawned) + ")");
  }
  std::string said;
  int passed_on = 0;  // the stop signal handed to the child
  char buffer[4096];
  for (;;) {
    if (const int sig = stop_signal(); sig && !passed_on) {
      ::kill(pid, sig);
      passed_on = sig;
    }
    pollfd p{pipe_fds[0], POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    const ssize_t n = ::read(pipe_fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    said.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(pipe_fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // A child that died of the stop signal we handed it (before its own handlers were in place) was
  // interrupted, not crashed: the line that says where the run stopped is ours to print.
  if (WIFSIGNALED(status) && said.find_first_not_of(" \n") == std::string::npos && WTERMSIG(status) != passed_on)
    said = "salsa: test '" + test.name + "' (" + test.source + ") died of " + signal_name(WTERMSIG(status)) +
           " in its own process (--isolate); behavior '" + test.behavior.name + "' (" +
           host.behavior(test.behavior.name).plugin().file.string() + ")\n";
  else if (WIFSIGNALED(status) && WTERMSIG(status) == passed_on && said.find_first_not_of(" \n") == std::string::npos)
    said = "salsa: " + signal_name(passed_on) + ": stopped test '" + test.name + "' (" + test.source +
           ") before it began (run again with --resume to redo it)\n";
  return {status, said};
}

/// --shard i/n, or from a Slurm job array (SLURM_ARRAY_TASK_ID, _MIN, _STEP and _COUNT); {0, 1}: the
/// whole queue.
std::pair<std::size_t, std::size_t> shard_option(const po::variables_map& vm) {
  const std::string allowed = " (allowed: i/n with n in [1, 1000000] and i in [0, n - 1], e.g. 0/4)";
  if (vm.count("shard")) {
    const std::string text = vm["shard"].as<std::string>();
    const auto slash = text.find('/');
    std::size_t i = 0, n = 0;
    const char* mid = text.data() + (slash == std::string::npos ? text.size() : slash);
    const auto a = std::from_chars(text.data(), mid, i);
    const auto b = slash == std::string::npos ? std::from_chars_result{mid, std::errc::invalid_argument}
                                               : std::from_chars(mid + 1, text.data() + text.size(), n);
    if (slash == 0 || a.ec != std::errc() || a.ptr != mid || b.ec != std::errc() || b.ptr != text.data() + text.size() || n < 1 ||
        n > 1000000 || i >= n)
      throw InputError("--shard: \"" + text + "\" is not a shard of the queue" + allowed);
    return {i, n};
  }
  auto env = [](const char* name) -> std::optional<long long> {
    const char* v = std::getenv(name);
    if (!v || !*v) return std::nullopt;
    long long x = 0;
    const auto [end, ec] = std::from_chars(v, v + std::strlen(v), x);
    if (ec != std::errc() || *end) throw InputError(std::string(name) + ": \"" + v + "\" is not a whole number (set by Slurm; or give --shard i/n)");
    return x;
  };
  const auto id = env("SLURM_ARRAY_TASK_ID"), count = env("SLURM_ARRAY_TASK_COUNT");
  if (!id || !count) return {0, 1};
  const long long min = env("SLURM_ARRAY_TASK_MIN").value_or(0), step = env("SLURM_ARRAY_TASK_STEP").value_or(1);
  const long long i = step > 0 ? (*id - min) / step : -1;
  if (*count < 1 || i < 0 || i >= *count)
    throw InputError("SLURM_ARRAY_TASK_ID: " + std::to_string(*id) + " is not in the job array (min " + std::to_string(min) + ", step " +
                     std::to_string(step) + ", count " + std::to_string(*count) + "; or give --shard i/n)");
  return {static_cast<std::size_t>(i), static_cast<std::size_t>(*count)};
}

/// The queue folder's summary, comparison and plots, from its test folders alone.
void finish_queue(const fs::path& out, const PluginHost& host, bool plots) {
  write_queue_summary(out, &host);
  if (cli::hooks().write_comparison) cli::hooks().write_comparison(out);
  if (plots && cli::hooks().draw_queue_plots) cli::hooks().draw_queue_plots(out);
}

int cmd_run(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "run", "FILE... [options]", run_options(), vm, "files", child_options())) return 0;
  const bool quiet = vm.count("quiet");
  const bool child = vm.count("only");  // one test of an --isolate run
  install_signal_handlers();
  if (child) ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // its run was killed: stop cleanly, not run on alone
  if (vm.count("isolate") && child) throw InputError("--isolate: not with --only");
  // Several ranks of mpirun: MPI hands out the tests (the child of an --isolate run is one test only).
  const bool mpi = !child && cli::under_mpirun();
  if (mpi && !cli::mpi_built())
    throw InputError("salsa runs under mpirun but was built without MPI: install libopenmpi-dev (Debian) and rebuild, or run without mpirun");
  if (mpi && vm.count("shard")) throw InputError("--shard: not under mpirun (MPI hands out the tests)");
  RunOptions options;
  options.out = vm["out"].as<std::string>();
  options.force = vm.count("force");
  options.resume = vm.count("resume");
  options.threads = static_cast<int>(whole_option(vm, "threads", 1024, "; 0 means all cores"));
  options.drones_csv = !vm.count("no-drones-csv");
  std::size_t jobs = vm.count("jobs") ? whole_option(vm, "jobs", 1024, "; 0 means all cores") : mpi ? 1 : 0;
  if (jobs == 0) jobs = static_cast<std::size_t>(std::max(1, tbb::info::default_concurrency()));
  const auto [shard, shards] = mpi || child ? std::pair<std::size_t, std::size_t>{0, 1} : shard_option(vm);
  PluginHost host;
  load_plugins(host, vm, !child);
  const auto tests = load_all(vm, host);
  // Every test valid before the first one runs; tests that will take hours are said so up front.
  for (const auto& t : tests) warn_workload(t, make_setup(t, host), quiet || child);
  // This process's share: one test (--isolate child), a shard (test k when k % n == i), or all.
  std::vector<std::size_t> mine;
  for (std::size_t k = 0; k < tests.size(); ++k)
    if (child ? tests[k].name == vm["only"].as<std::string>() : k % shards == shard) mine.push_back(k);
  if (child && mine.empty()) throw InputError("--only: no test named \"" + vm["only"].as<std::string>() + "\"");
  jobs = std::max<std::size_t>(1, std::min(jobs, mpi ? jobs : mine.size()));
  // Tests side by side each get one thread, unless --threads says otherwise: more would oversubscribe.
  if (jobs > 1 && vm["threads"].defaulted()) options.threads = 1;

  std::optional<cli::MpiRun> world;
  if (mpi) world.emplace();
  const bool root = !world || world->rank() == 0;
  // The checks of the output folder: by rank 0 only under MPI (the others wait for its verdict).
  if (root) {
    bool ok = false;
    try {
      std::vector<TestSpec> checked;
      for (std::size_t k : mine) checked.push_back(tests[k]);
      if (world) checked = tests;
      std::optional<QueueRecord> record;  // an --isolate child's run has recorded its queue already
      if (!child) {
        std::vector<std::string> command{"salsa"};
        command.insert(command.end(), argv, argv + argc);
        record = queue_record(tests, host, command);
        check_queue_folder(options.out, *record, options.resume, options.force);
      }
      check_outputs(checked, host, options);
      if (record) claim_queue_folder(options.out, *record, options.resume, options.force);
      ok = true;
    } catch (...) {
      if (world) world->agree(false);
      throw;
    }
    if (world) world->agree(ok);
  } else if (!world->agree(false)) {
    return 2;  // rank 0 said why
  }

  cli::QueueRunOptions run;
  run.jobs = jobs;
  run.quiet = quiet || child;
  run.plots = !vm.count("no-plots") && !child;
  run.terminal = !world && ::isatty(STDOUT_FILENO);
  run.expected = world ? (root ? tests.size() : 0) : mine.size();
  if (vm.count("isolate"))
    run.isolated = [&, threads = vm["threads"].defaulted() ? std::to_string(options.threads) : ""](const TestSpec& t) {
      return run_isolated(t, host, argc, argv, threads);
    };
  // From here a stop is the run's to handle: it ends the test that steps (the watchdog steps in only
  // while one does, a step may take minutes) and writes what it owes; --isolate's children stop themselves.
  stop_may_exit(false);
  std::unique_ptr<cli::Dispatch> dispatch = world ? world->dispatch(tests.size()) : std::make_unique<cli::ListDispatch>(mine);
  const cli::QueueResult result = cli::run_queue(tests, host, options, run, *dispatch);
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

int cmd_summarize(int argc, char** argv) {
  po::options_description o("summarize options");
  o.add_options()("out", po::value<std::string>(), "a queue's output folder (what 'salsa run --out' wrote)")(
      "no-plots", "do not draw the queue plots");
  po::variables_map vm;
  if (!parse(argc, argv, "summarize", "OUT [options]", o, vm, "out")) return 0;
  if (!vm.count("out")) throw InputError("summarize: missing OUT (the folder 'salsa run --out OUT' wrote)");
  const fs::path out = vm["out"].as<std::string>();
  std::error_code ec;
  if (!fs::is_directory(out, ec)) throw InputError("summarize: " + out.string() + " is not a folder (allowed: the folder 'salsa run --out' wrote)");
  PluginHost host;
  load_plugins(host, vm, false);
  finish_queue(out, host, !vm.count("no-plots"));
  if (!vm.count("quiet")) std::cout << "wrote " << (out / "summary.csv").string() << std::endl;
  return 0;
}

int cmd_validate(int argc, char** argv) {
  po::options_description o("validate options");
  o.add_options()("files", po::value<std::vector<std::string>>(), "test, queue or map files")(
      "seed", po::value<std::string>(), "queue seed, as for run")("yes,y", "allow a queue of more than 10,000 tests");
  po::variables_map vm;
  if (!parse(argc, argv, "validate", "FILE... [options]", o, vm, "files")) return 0;
  if (!vm.count("files")) throw InputError("validate: missing FILE");
  const QueueOptions options = queue_options(vm);
  PluginHost host;
  load_plugins(host, vm, true);
  for (const auto& f : vm["files"].as<std::vector<std::string>>()) {
    if (is_map_file(f)) {
      load_map_file(f, host);
      if (!vm.count("quiet")) std::cout << f << ": ok (map)\n";
      continue;
    }
    const auto tests = load_queue(f, host, options).tests;
    for (const auto& t : tests) warn_workload(t, make_setup(t, host), vm.count("quiet"));
    if (!vm.count("quiet")) std::cout << f << ": ok (" << tests.size() << (tests.size() == 1 ? " test)\n" : " tests)\n");
  }
  return 0;
}

/// `salsa queue expand FILE`: the count, then a line per test in the order they run.
int cmd_queue(int argc, char** argv) {
  po::options_description o("queue options");
  o.add_options()("seed", po::value<std::string>(), "queue seed, as for run")("yes,y", "allow a queue of more than 10,000 tests");
  po::options_description hidden;
  hidden.add_options()("args", po::value<std::vector<std::string>>(), "");
  po::variables_map vm;
  if (!parse(argc, argv, "queue", "expand FILE [options]", o, vm, "args", hidden)) return 0;
  const auto args = vm.count("args") ? vm["args"].as<std::vector<std::string>>() : std::vector<std::string>{};
  if (args.empty() || args[0] != "expand")
    throw InputError("queue: " + (args.empty() ? std::string("missing action") : "unknown action '" + args[0] + "'") + " (allowed: expand)");
  if (args.size() != 2) throw InputError("queue expand: " + std::string(args.size() < 2 ? "missing FILE" : "one FILE at a time"));
  PluginHost host;
  load_plugins(host, vm, true);
  const Queue queue = load_queue(args[1], host, queue_options(vm));
  // One row per test, columns as wide as their longest entry.
  std::vector<std::vector<std::string>> rows;
  for (const TestSpec& t : queue.tests) {
    std::string targets = "targets=" + std::to_string(t.targets);
    if (t.targets > 0) {
      const std::string kind = describe_choice(t.target, host.target_kind(t.target.name).factory.parameters);
      if (kind != "tree") targets += " " + kind;
    }
    rows.push_back({t.name, variant(t, host), "drones=" + std::to_string(t.drones), targets,
                    "map=" + (t.map_file.empty() ? describe_choice(t.map, host.map(t.map.name).factory.parameters) : t.map_file),
                    "drone=" + t.drone.name, "repeat=" + std::to_string(t.repeat), "seed=" + std::to_string(t.seed)});
  }
  std::vector<std::size_t> width(rows.empty() ? 0 : rows[0].size(), 0);
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  std::cout << queue.tests.size() << (queue.tests.size() == 1 ? " test\n" : " tests\n");
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c) line += row[c] + (c + 1 < row.size() ? std::string(width[c] - row[c].size() + 2, ' ') : "");
    std::cout << line << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h" || std::string(argv[1]) == "help") {
    std::cout << usage;
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  if (command == "--version") {
    std::cout << "salsa " << salsa_version() << "\n";
    return 0;
  }
  try {
    if (command == "run") return cmd_run(argc - 1, argv + 1);
    if (command == "summarize") return cmd_summarize(argc - 1, argv + 1);
    if (command == "validate") return cmd_validate(argc - 1, argv + 1);
    if (command == "queue") return cmd_queue(argc - 1, argv + 1);
    if (command == "plugins") return cmd_plugins(argc - 1, argv + 1);
    if (command == "describe") return cmd_describe(argc - 1, argv + 1);
    if (command == "bench") return cmd_bench(argc - 1, argv + 1);
    if (command == "plot") return cmd_plot(argc - 1, argv + 1);
    if (command == "new-plugin") return cmd_new_plugin(argc - 1, argv + 1);
    std::cerr << "salsa: unknown command '" << command << "' (allowed: run, summarize, validate, queue, plugins, describe, bench, plot, new-plugin)\n";
    return 2;
  } catch (const po::error& e) {
    std::cerr << "salsa " << command << ": " << e.what() << " (see 'salsa " << command << " --help')\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << "salsa: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "salsa: " << e.what() << "\n";
    return 1;
  }
}
