#pragma once
// The subcommands, one file each: run.cpp, summarize.cpp, validate.cpp, queue_expand.cpp,
// plugins.cpp (plugins, describe), bench.cpp, plot.cpp, new_plugin.cpp, tune.cpp, suite.cpp, export.cpp. Each takes the arguments
// after its name and returns the exit status; bad input throws InputError (main prints it, status 2).
#include <boost/program_options/variables_map.hpp>

#include <filesystem>
#include <string>

namespace salsa { class PluginHost; }

int cmd_run(int argc, char** argv);
int cmd_summarize(int argc, char** argv);
int cmd_validate(int argc, char** argv);
int cmd_queue(int argc, char** argv);
int cmd_plugins(int argc, char** argv);
int cmd_describe(int argc, char** argv);
int cmd_bench(int argc, char** argv);
int cmd_plot(int argc, char** argv);
int cmd_new_plugin(int argc, char** argv);
int cmd_tune(int argc, char** argv);
int cmd_suite(int argc, char** argv);
int cmd_export(int argc, char** argv);

/// salsa bench queue FILE (cli/bench_queue.cpp).
int bench_queue(const boost::program_options::variables_map& vm, const salsa::PluginHost& host, const std::string& cpu);
/// salsa bench abm-flocking (cli/bench_abm.cpp).
int bench_abm_flocking(const boost::program_options::variables_map& vm, const salsa::PluginHost& host, const std::string& cpu);

namespace salsa::cli {
/// The queue folder's summary.csv, comparison.csv and (with `draw_plots`) queue plots, from its test
/// folders alone (summarize.cpp). Returns what the comparison took from the folders' order for want of
/// OUT/queue.json ("" when nothing).
std::string finish_queue(const std::filesystem::path& out, const PluginHost& host, bool draw_plots);
/// A tune folder's plots (convergence, each parameter, the Pareto front) from its candidates.csv and
/// tune_plots.json alone (tune_folder_plots.cpp); call plots::start_plotting() first. Throws InputError.
void draw_tune_folder(const std::filesystem::path& out);
}  // namespace salsa::cli
