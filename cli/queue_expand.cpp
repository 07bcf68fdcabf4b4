// salsa queue expand FILE: the tests a queue expands to, in the order they run.
#include <iostream>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "commands.hpp"
#include "options.hpp"

using namespace salsa;
using namespace salsa::cli;

/// `salsa queue expand FILE`: the count, then a line per test in the order they run.
int cmd_queue(int argc, char** argv) {
  po::options_description o("queue options");
  po::options_description hidden;
  hidden.add_options()("args", po::value<std::vector<std::string>>(), "");
  po::variables_map vm;
  if (!parse(argc, argv, "queue", "expand FILE [options]", o, vm, plugin_options | queue_options, positional("args"), hidden)) return 0;
  const auto args = vm.count("args") ? vm["args"].as<std::vector<std::string>>() : std::vector<std::string>{};
  if (args.empty() || args[0] != "expand")
    throw InputError("queue: " + (args.empty() ? std::string("missing action") : "unknown action '" + args[0] + "'") + " (allowed: expand)");
  if (args.size() != 2) throw InputError("queue expand: " + std::string(args.size() < 2 ? "missing FILE" : "one FILE at a time"));
  PluginHost host;
  load_plugins(host, vm, true);
  const Queue queue = load_queue(args[1], host, queue_settings(vm));
  // One row per test, columns as wide as their longest entry.
  std::vector<std::vector<std::string>> rows;
  for (const TestSpec& t : queue.tests) {
    std::string targets = "targets=" + std::to_string(t.targets);
    if (t.targets > 0) {
      const std::string kind = describe_choice(t.target, host.target_kind(t.target.name).factory.parameters);
      if (kind != "tree") targets += " " + kind;
    }
    rows.push_back({t.name, variant(t, host), "drones=" + std::to_string(t.drone_total()), targets,
                    "map=" + (t.map_file.empty() ? describe_choice(t.map, host.map(t.map.name).factory.parameters) : t.map_file),
                    "drone=" + t.groups[0].drone.name, "repeat=" + std::to_string(t.repeat), "seed=" + std::to_string(t.seed)});
    if (!t.condition.empty()) rows.back().insert(rows.back().begin() + 2, "condition=" + t.condition);  // every test of such a queue has one
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

