// What the salsa command does with its arguments: names the subcommands and answers errors; each
// subcommand is in a file of its own (commands.hpp), the shared options in options.hpp. The program
// (main.cpp) and the Python package's runner (embed.hpp) call it.
#include <boost/program_options/errors.hpp>

#include <iostream>
#include <string>

#include "salsa/core/experiments/test_spec.hpp"
#include "commands.hpp"
#include "embed.hpp"

namespace po = boost::program_options;
using namespace salsa;

namespace {

const char* usage = R"(usage: salsa <command> [options]

commands:
  run FILE...        run tests (a test, a list of tests, or a queue with a sweep) and write their data
  summarize OUT      write OUT/summary.csv (one row per test), comparison and plots from a queue's output folder
  tune FILE          tune a test's parameters (pagmo2, NLopt; racing, held-out validation): tune.csv, best.json
  suite BEHAVIOR     run a behavior on the benchmark suite's tasks and place it among the reference behaviors
  export FOLDER      share a finished test: --mcap FILE, --html DIR (a web page), --video FILE.mp4
  validate FILE...   check test, queue and map files without running them
  queue expand FILE  print the tests a queue expands to (count, then one line each)
  plugins            list the plugins found, the folders searched and the files refused
  describe NAME      print a plugin's parameters (name, default, min, max, unit, meaning); NAME drone,
                     comm, wind or failures: that model's settings
  bench WORKLOAD     measure speed (table1, scale)
  plot FOLDER|FILE   redraw the plots of a results or test folder; chart a bench JSON or summary.csv
  new-plugin KIND NAME  write NAME/: a plugin (behavior, target, map, contact-handler, metric, wind), its test and CMakeLists.txt

'salsa <command> --help' shows the options of a command.
)";

}  // namespace

/// The last safety net of "one line per failure": a message that still holds a line break (plugin
/// text passed on somewhere) is joined.
static std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

int salsa::cli::run_command(int argc, char** argv) {
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
    if (command == "export") return cmd_export(argc - 1, argv + 1);
    if (command == "validate") return cmd_validate(argc - 1, argv + 1);
    if (command == "queue") return cmd_queue(argc - 1, argv + 1);
    if (command == "plugins") return cmd_plugins(argc - 1, argv + 1);
    if (command == "describe") return cmd_describe(argc - 1, argv + 1);
    if (command == "bench") return cmd_bench(argc - 1, argv + 1);
    if (command == "plot") return cmd_plot(argc - 1, argv + 1);
    if (command == "new-plugin") return cmd_new_plugin(argc - 1, argv + 1);
    if (command == "tune") return cmd_tune(argc - 1, argv + 1);
    if (command == "suite") return cmd_suite(argc - 1, argv + 1);
    std::cerr << "salsa: unknown command '" << command << "' (allowed: run, tune, suite, summarize, export, validate, queue, plugins, describe, bench, plot, new-plugin)\n";
    return 2;
  } catch (const po::error& e) {
    std::cerr << "salsa " << command << ": " << e.what() << " (see 'salsa " << command << " --help')\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << "salsa: " << one_line(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "salsa: " << one_line(e.what()) << "\n";
    return 1;
  }
}


salsa::cli::Embedding& salsa::cli::embedding() {
  static Embedding e;
  return e;
}
