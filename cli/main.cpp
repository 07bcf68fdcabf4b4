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
#include <sstream>

#include "salsa/core/plugin_host.hpp"
#include "salsa/core/runner.hpp"
#include "salsa/core/test_spec.hpp"
#include "commands.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using namespace salsa;

namespace {

const char* usage = R"(usage: salsa <command> [options]

commands:
  run FILE...        run tests (a test, a list of tests, or {"tests": [...]}) and write their data
  validate FILE...   check test and map files without running them
  plugins            list the plugins found, the folders searched and the files refused
  describe NAME      print a plugin's parameters (name, default, min, max, unit, meaning)
  bench WORKLOAD     measure speed (table1, scale)
  plot FILE          PNG chart of a bench JSON file or a summary.csv column over time

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
      "seed", po::value<std::string>(), "seed for every test, a whole number in [0, 2^53] (the i-th test of a file gets SEED + i)")(
      "time", po::value<std::string>(), "simulated seconds per test (overrides the files)")(
      "log-interval", po::value<std::string>(), "seconds between logged rows (overrides the files)")(
      "threads", po::value<std::string>()->default_value("0"), "threads for each simulation's decide phase (0: all cores)")(
      "no-drones-csv", "do not write drones.csv (it is the largest file)")(
      "resume", "skip tests whose output folder holds the identical finished test")(
      "force", "replace the output folders salsa wrote for these tests")(
      "isolate", "run each test in its own process: a crashing plugin fails that test only");
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

/// Loads every file's tests and applies the command-line overrides (with the same checks as the files).
std::vector<TestSpec> load_all(const po::variables_map& vm, const PluginHost& host) {
  if (!vm.count("files")) throw InputError("missing FILE (a test file, see examples/)");
  std::optional<std::uint64_t> seed;
  if (vm.count("seed")) seed = whole_option(vm, "seed", static_cast<std::uint64_t>(max_seed));
  std::vector<TestSpec> all;
  for (const auto& f : vm["files"].as<std::vector<std::string>>()) {
    auto tests = load_tests(f, host);
    for (std::size_t i = 0; i < tests.size(); ++i) {
      TestSpec& t = tests[i];
      if (seed) {
        if (*seed + i > static_cast<std::uint64_t>(max_seed))
          throw InputError("--seed: " + std::to_string(*seed) + " + " + std::to_string(i) + " for " + t.source +
                           " is out of range (allowed: SEED + i up to 9007199254740992, i counting the tests of a file)");
        t.seed = *seed + i;
      }
      if (vm.count("time")) t.time = seconds_option(vm, "time", t);
      if (vm.count("log-interval")) t.log_interval = seconds_option(vm, "log-interval", t);
    }
    for (auto& t : tests) {
      for (const auto& other : all)
        if (other.name == t.name) throw InputError(t.source + ": name: \"" + t.name + "\" is already used by " + other.source);
      all.push_back(std::move(t));
    }
  }
  return all;
}

/// Whether a run was stopped by SIGINT/SIGTERM: prints the note and gives the exit status (0: go on).
int stopped_before(const std::string& what) {
  const int sig = stop_signal();
  if (!sig) return 0;
  std::cerr << "salsa: " << signal_name(sig) << ": stopped before " << what << " (run again with --resume for the rest)\n";
  return 128 + sig;
}

/// --isolate: runs one test in a new process (this executable, the same arguments, --only NAME) and
/// waits for it, passing SIGINT/SIGTERM on. Its stderr goes through this process, so a child that
/// dies without a word still gets its line. Returns the child's wait status.
int run_isolated(const TestSpec& test, const PluginHost& host, int argc, char** argv) {
  std::vector<std::string> args{"salsa", "run"};
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) != "--isolate") args.emplace_back(argv[i]);
  args.insert(args.end(), {"--only", test.name});
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
    throw std::runtime_error("test '" + test.name + "': cannot start its process (" + std::strerror(spawned) + ")");
  }
  bool said_something = false;
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
    said_something = true;
    std::cerr.write(buffer, n).flush();
  }
  ::close(pipe_fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // A child that died of the stop signal we handed it (before its own handlers were in place) was
  // interrupted, not crashed: the line that says where the run stopped is ours to print.
  if (WIFSIGNALED(status) && !said_something && WTERMSIG(status) != passed_on)
    std::cerr << "salsa: test '" << test.name << "' (" << test.source << ") died of " << signal_name(WTERMSIG(status))
              << " in its own process (--isolate); behavior '" << test.behavior.name << "' ("
              << host.behavior(test.behavior.name).plugin().file.string() << ")\n";
  return status;
}

int cmd_run(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "run", "FILE... [options]", run_options(), vm, "files", child_options())) return 0;
  const bool quiet = vm.count("quiet");
  const bool child = vm.count("only");  // one test of an --isolate run
  install_signal_handlers();
  if (child) ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // its run was killed: stop cleanly, not run on alone
  RunOptions options;
  options.out = vm["out"].as<std::string>();
  options.force = vm.count("force");
  options.resume = vm.count("resume");
  options.threads = static_cast<int>(whole_option(vm, "threads", 1024, "; 0 means all cores"));
  options.drones_csv = !vm.count("no-drones-csv");
  if (vm.count("isolate") && child) throw InputError("--isolate: not with --only");
  PluginHost host;
  load_plugins(host, vm, !child);
  const auto tests = load_all(vm, host);
  // Every test valid before the first one runs; tests that will take hours are said so up front.
  for (const auto& t : tests) warn_workload(t, make_setup(t, host), quiet || child);
  // An --isolate child checks the output of its own test only: the others may be done by now.
  std::vector<TestSpec> mine = tests;
  if (child) {
    std::erase_if(mine, [&](const TestSpec& t) { return t.name != vm["only"].as<std::string>(); });
    if (mine.empty()) throw InputError("--only: no test named \"" + vm["only"].as<std::string>() + "\"");
  }
  check_outputs(mine, host, options);
  bool failed = false;
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const TestSpec& test = tests[i];
    if (child && test.name != vm["only"].as<std::string>()) continue;
    if (const int status = stopped_before("test '" + test.name + "'")) return status;
    std::ostringstream line;
    line << "[" << i + 1 << "/" << tests.size() << "] " << test.name << ": ";
    if (vm.count("isolate") && !already_done(test, host, options)) {
      const int status = run_isolated(test, host, argc, argv);
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
      if (stop_signal() && (code == 130 || code == 143)) return 128 + stop_signal();  // it said so itself
      failed = failed || status != 0;
      continue;  // the child printed its line
    }
    try {
      const RunResult r = run_test(test, host, options);
      if (r.skipped) line << "already complete, skipped";
      else
        line << std::fixed << std::setprecision(2) << test.time << " s simulated in " << r.wall_seconds << " s, " << r.found
             << "/" << r.targets << " targets found -> " << r.folder.string();
    } catch (const TestFailure& e) {
      std::cerr << "salsa: " << e.what() << std::endl;
      failed = true;
      continue;  // the other tests go on
    } catch (const Interrupted& e) {
      std::cerr << "salsa: " << e.what() << std::endl;
      return 128 + e.signal;
    }
    if (!quiet) std::cout << line.str() << std::endl;
  }
  if (!quiet && !child) std::cout << "results in " << options.out.string() << std::endl;
  return failed ? 1 : 0;
}

int cmd_validate(int argc, char** argv) {
  po::options_description o("validate options");
  o.add_options()("files", po::value<std::vector<std::string>>(), "test or map files");
  po::variables_map vm;
  if (!parse(argc, argv, "validate", "FILE... [options]", o, vm, "files")) return 0;
  if (!vm.count("files")) throw InputError("validate: missing FILE");
  PluginHost host;
  load_plugins(host, vm, true);
  for (const auto& f : vm["files"].as<std::vector<std::string>>()) {
    if (is_map_file(f)) {
      load_map_file(f, host);
      if (!vm.count("quiet")) std::cout << f << ": ok (map)\n";
      continue;
    }
    const auto tests = load_tests(f, host);
    for (const auto& t : tests) warn_workload(t, make_setup(t, host), vm.count("quiet"));
    if (!vm.count("quiet")) std::cout << f << ": ok (" << tests.size() << (tests.size() == 1 ? " test)\n" : " tests)\n");
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
    if (command == "validate") return cmd_validate(argc - 1, argv + 1);
    if (command == "plugins") return cmd_plugins(argc - 1, argv + 1);
    if (command == "describe") return cmd_describe(argc - 1, argv + 1);
    if (command == "bench") return cmd_bench(argc - 1, argv + 1);
    if (command == "plot") return cmd_plot(argc - 1, argv + 1);
    std::cerr << "salsa: unknown command '" << command << "' (allowed: run, validate, plugins, describe, bench, plot)\n";
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
