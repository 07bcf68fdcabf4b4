// salsa: the headless front-end. Thin: parses the command line and calls libsalsa.
#include <boost/program_options.hpp>

#include <array>
#include <cstdio>
#include <iomanip>
#include <iostream>
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

/// Parses a subcommand's arguments; returns false when --help was printed.
bool parse(int argc, char** argv, const std::string& command, const std::string& synopsis,
           po::options_description options, po::variables_map& vm, const char* positional = nullptr) {
  options.add(common_options());
  po::positional_options_description pos;
  if (positional) pos.add(positional, -1);
  po::store(po::command_line_parser(argc, argv).options(options).positional(pos).run(), vm);
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
    for (const auto& f : host.failures())
      std::cerr << "salsa: warning: plugin " << f.file.string() << " skipped: " << f.reason << "\n";
}

int cmd_plugins(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "plugins", "[options]", po::options_description("plugins options"), vm)) return 0;
  PluginHost host;
  load_plugins(host, vm, false);
  std::cout << "Folders searched, in order:\n";
  for (const auto& d : host.searched())
    std::cout << "  " << std::left << std::setw(18) << d.origin << " " << d.path.string()
              << (fs::is_directory(d.path) ? "" : "  (missing)") << "\n";
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

int cmd_describe(int argc, char** argv) {
  po::options_description o("describe options");
  o.add_options()("name", po::value<std::string>(), "plugin name (behavior, target kind, map or contact handler)");
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
  if (!found) throw InputError("describe: no plugin named '" + name + "' (see 'salsa plugins')");
  return 0;
}

po::options_description run_options() {
  po::options_description o("run options");
  o.add_options()("files", po::value<std::vector<std::string>>(), "test files")(
      "out,o", po::value<std::string>()->default_value("results"), "output folder; each test writes to OUT/<test name>/")(
      "seed", po::value<std::uint64_t>(), "seed for every test (the i-th test of a file gets SEED + i)")(
      "time", po::value<double>(), "simulated seconds per test (overrides the files)")(
      "log-interval", po::value<double>(), "seconds between logged rows (overrides the files)")(
      "threads", po::value<int>()->default_value(0), "threads for each simulation's decide phase (0: all cores)")(
      "no-drones-csv", "do not write drones.csv (it is the largest file)")(
      "resume", "skip tests whose output folder is complete")("force", "replace existing output folders");
  return o;
}

/// Loads every file's tests and applies the command-line overrides (with the same checks as the files).
std::vector<TestSpec> load_all(const po::variables_map& vm, const PluginHost& host) {
  if (!vm.count("files")) throw InputError("missing FILE (a test file, see examples/)");
  std::vector<TestSpec> all;
  for (const auto& f : vm["files"].as<std::vector<std::string>>()) {
    auto tests = load_tests(f, host);
    for (std::size_t i = 0; i < tests.size(); ++i) {
      TestSpec& t = tests[i];
      if (vm.count("seed")) t.seed = vm["seed"].as<std::uint64_t>() + i;
      if (vm.count("time")) {
        const double v = vm["time"].as<double>();
        if (!(v >= t.dt && v <= 1e7)) throw InputError("--time: " + Parameter::format(v) + " is out of range (allowed: [" + Parameter::format(t.dt) + ", 10000000] s)");
        t.time = v;
      }
      if (vm.count("log-interval")) {
        const double v = vm["log-interval"].as<double>();
        if (!(v >= t.dt && v <= 1e7)) throw InputError("--log-interval: " + Parameter::format(v) + " is out of range (allowed: [" + Parameter::format(t.dt) + ", 10000000] s)");
        t.log_interval = v;
      }
    }
    for (auto& t : tests) {
      for (const auto& other : all)
        if (other.name == t.name) throw InputError(t.source + ": name: \"" + t.name + "\" is already used by " + other.source);
      all.push_back(std::move(t));
    }
  }
  return all;
}

int cmd_run(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "run", "FILE... [options]", run_options(), vm, "files")) return 0;
  const bool quiet = vm.count("quiet");
  PluginHost host;
  load_plugins(host, vm, true);
  RunOptions options;
  options.out = vm["out"].as<std::string>();
  options.force = vm.count("force");
  options.resume = vm.count("resume");
  options.threads = vm["threads"].as<int>();
  if (options.threads < 0 || options.threads > 1024)
    throw InputError("--threads: " + std::to_string(options.threads) + " is out of range (allowed: 0 to 1024; 0 means all cores)");
  options.drones_csv = !vm.count("no-drones-csv");
  const auto tests = load_all(vm, host);
  for (const auto& t : tests) make_setup(t, host);  // every test valid before the first one runs
  check_outputs(tests, options);
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const RunResult r = run_test(tests[i], host, options);
    if (quiet) continue;
    std::ostringstream line;
    line << "[" << i + 1 << "/" << tests.size() << "] " << tests[i].name << ": ";
    if (r.skipped) line << "already complete, skipped";
    else
      line << std::fixed << std::setprecision(2) << tests[i].time << " s simulated in " << r.wall_seconds << " s, " << r.found
           << "/" << r.targets << " targets found -> " << r.folder.string();
    std::cout << line.str() << std::endl;
  }
  if (!quiet) std::cout << "results in " << options.out.string() << std::endl;
  return 0;
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
    for (const auto& t : tests) make_setup(t, host);
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
