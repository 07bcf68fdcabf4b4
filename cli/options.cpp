#include "options.hpp"
#include "embed.hpp"

#include <charconv>
#include <cmath>
#include <iostream>

namespace salsa::cli {

namespace fs = std::filesystem;

namespace {

/// The one declaration of the options several subcommands share.
po::options_description shared_options(unsigned shared) {
  po::options_description o("common options");
  o.add_options()("help,h", "show this help");
  if (shared & plugin_options)
    o.add_options()("plugin-dir", po::value<std::vector<std::string>>()->composing(),
                    "also search this folder for plugins (repeatable, searched first)")("quiet,q", "print only errors");
  // Numbers are read as text and checked by whole_option, so that "-1" or "1e400" get a one-line answer.
  if (shared & queue_options)
    o.add_options()("seed", po::value<std::string>(),
                    "queue seed of every file, a whole number in [0, 2^53]: each test's seed is paired from it (over the seeds in the files)")(
        "yes,y", "allow a queue of more than 10,000 tests");
  return o;
}

}  // namespace

po::positional_options_description positional(const char* name, int max) {
  po::positional_options_description pos;
  pos.add(name, max);
  return pos;
}

bool parse(int argc, char** argv, const std::string& command, const std::string& synopsis, po::options_description options,
           po::variables_map& vm, unsigned shared, const po::positional_options_description& pos,
           const po::options_description& hidden) {
  options.add(shared_options(shared));
  po::options_description all;
  all.add(options).add(hidden);
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
  if (const auto& load = cli::embedding().load) load(host, plugin_dirs(vm));
  else host.load(PluginHost::default_search_path(plugin_dirs(vm)));
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


/// A decimal number given on the command line, or nullopt when the text is not one.
std::optional<double> decimal(const std::string& text) {
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec == std::errc::invalid_argument || end != text.data() + text.size()) return std::nullopt;
  return ec == std::errc::result_out_of_range ? HUGE_VAL : v;  // "1e400": out of range, not "not a number"
}

/// A whole number in [0, hi] given on the command line, or InputError naming the option.
std::uint64_t whole_option(const po::variables_map& vm, const char* name, std::uint64_t hi, const std::string& note) {
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
QueueOptions queue_settings(const po::variables_map& vm) {
  QueueOptions o;
  if (vm.count("seed")) o.seed = whole_option(vm, "seed", max_seed);
  o.yes = vm.count("yes");
  return o;
}


}  // namespace salsa::cli
