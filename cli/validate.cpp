// salsa validate FILE...: test, queue and map files checked as a run would, without running them.
#include <iostream>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/shared_state.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "commands.hpp"
#include "options.hpp"

using namespace salsa;
using namespace salsa::cli;

int cmd_validate(int argc, char** argv) {
  po::options_description o("validate options");
  o.add_options()("files", po::value<std::vector<std::string>>(), "test, queue or map files");
  po::variables_map vm;
  if (!parse(argc, argv, "validate", "FILE... [options]", o, vm, plugin_options | queue_options, positional("files"))) return 0;
  if (!vm.count("files")) throw InputError("validate: missing FILE");
  const QueueOptions options = queue_settings(vm);
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
    if (const std::string line = shared_state_warning(tests, host); !line.empty() && !vm.count("quiet"))
      std::cerr << "salsa: warning: " << f << ": the queue " << line << "\n";
    if (!vm.count("quiet")) std::cout << f << ": ok (" << tests.size() << (tests.size() == 1 ? " test)\n" : " tests)\n");
  }
  return 0;
}

