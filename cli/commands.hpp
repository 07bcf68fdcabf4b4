#pragma once
// Subcommands implemented outside main.cpp.
int cmd_bench(int argc, char** argv);
int cmd_plot(int argc, char** argv);
int cmd_new_plugin(int argc, char** argv);

#include <boost/program_options/variables_map.hpp>
#include <string>
namespace salsa { class PluginHost; }
/// salsa bench queue FILE (cli/bench_queue.cpp).
int bench_queue(const boost::program_options::variables_map& vm, const salsa::PluginHost& host, const std::string& cpu);
