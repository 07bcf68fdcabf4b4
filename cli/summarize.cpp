// salsa summarize OUT: a queue folder's summary.csv, comparison.csv and plots, from its test folders alone.
#include <iostream>

#include "salsa/core/results/comparison.hpp"
#include "salsa/core/results/queue_summary.hpp"
#include "salsa/plots/results.hpp"
#include "commands.hpp"
#include "options.hpp"

namespace fs = std::filesystem;
using namespace salsa;
using namespace salsa::cli;

namespace salsa::cli {

/// The queue folder's summary, comparison and plots, from its test folders alone; what the comparison
/// took from the folders' order for want of OUT/queue.json ("" when nothing).
std::string finish_queue(const fs::path& out, const PluginHost& host, bool draw_plots) {
  write_queue_summary(out, &host);
  std::string assumed = write_comparison(out);
  write_comparison_notes(out);
  if (draw_plots) plots::draw_queue_plots(out);
  return assumed;
}


}  // namespace salsa::cli

int cmd_summarize(int argc, char** argv) {
  po::options_description o("summarize options");
  o.add_options()("out", po::value<std::string>(), "a queue's output folder (what 'salsa run --out' wrote)")(
      "no-plots", "do not draw the queue plots");
  po::variables_map vm;
  if (!parse(argc, argv, "summarize", "OUT [options]", o, vm, plugin_options, positional("out"))) return 0;
  if (!vm.count("out")) throw InputError("summarize: missing OUT (the folder 'salsa run --out OUT' wrote)");
  const fs::path out = vm["out"].as<std::string>();
  std::error_code ec;
  if (!fs::is_directory(out, ec)) throw InputError("summarize: " + out.string() + " is not a folder (allowed: the folder 'salsa run --out' wrote)");
  // A tune's folder has its own summary, report and plots (salsa tune --resume rewrites them).
  if (holds_results(out) && holds_tune(out))
    throw InputError("summarize: " + out.string() + " holds a tune's results (tune.json), not a queue's (allowed: the folder 'salsa run --out' " +
                     "wrote; 'salsa tune FILE --out " + out.string() + " --resume' rewrites a tune's files)");
  PluginHost host;
  load_plugins(host, vm, false);
  // Test folders copied out of a queue's folder keep neither its baseline condition nor its reference.
  if (const std::string assumed = finish_queue(out, host, !vm.count("no-plots")); !assumed.empty())
    std::cerr << "salsa: warning: summarize: " << out.string() << " has no queue.json: " << assumed << std::endl;
  if (!vm.count("quiet"))
    for (const std::string& note : write_comparison_notes(out)) std::cerr << "salsa: warning: " << note << std::endl;
  if (!vm.count("quiet")) std::cout << "wrote " << (out / "summary.csv").string() << std::endl;
  return 0;
}

