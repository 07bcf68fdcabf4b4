#pragma once
// The command line, shared by every subcommand: the common options declared once (--help,
// --plugin-dir, --quiet, --seed, --yes), one parser, and the checks of numbers given as text (a
// one-line refusal naming the option and what is allowed, never a wrap-around or a parser's message).
#include <boost/program_options.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::cli {

namespace po = boost::program_options;

/// The shared options a subcommand takes besides --help (flags, or-ed).
enum Shared : unsigned {
  help_only = 0,
  plugin_options = 1u << 0,  ///< --plugin-dir (repeatable) and --quiet
  queue_options = 1u << 1,   ///< --seed (the queue seed) and --yes (queues over 10,000 tests)
};

/// The positional arguments: `name`, up to `max` of them (-1: any number).
po::positional_options_description positional(const char* name, int max = -1);

/// Parses a subcommand's arguments with `options`, the `shared` ones and `hidden` ones (accepted,
/// not shown); returns false when --help was printed ("usage: salsa COMMAND SYNOPSIS" and the options).
bool parse(int argc, char** argv, const std::string& command, const std::string& synopsis, po::options_description options,
           po::variables_map& vm, unsigned shared, const po::positional_options_description& positional = {},
           const po::options_description& hidden = po::options_description());

/// --plugin-dir's folders, in order.
std::vector<std::filesystem::path> plugin_dirs(const po::variables_map& vm);

/// Loads the plugins of the default search path (with --plugin-dir first); when `report_failures`
/// and not --quiet, a warning line per refused plugin file or registration.
void load_plugins(PluginHost& host, const po::variables_map& vm, bool report_failures);

/// Says so on stderr when a test will likely take hours (estimated neighbours per drone and steps).
void warn_workload(const TestSpec& test, const SimulationSetup& setup, bool quiet);


/// A decimal number given on the command line, or nullopt when the text is not one ("1e400": HUGE_VAL).
std::optional<double> decimal(const std::string& text);

/// A whole number in [0, hi] given on the command line, or InputError naming the option.
std::uint64_t whole_option(const po::variables_map& vm, const char* name, std::uint64_t hi, const std::string& note = "");

/// --time / --log-interval: a number of seconds in [dt, 1e7] of each test.
double seconds_option(const po::variables_map& vm, const char* name, const TestSpec& t);

/// --seed and --yes as QueueOptions.
QueueOptions queue_settings(const po::variables_map& vm);

}  // namespace salsa::cli
