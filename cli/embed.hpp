#pragma once
// The salsa command run by another program (the Python package, python/salsa/_program.py): a process
// of its own that is the salsa program with more behaviors, so that a queue of tests naming them runs
// through the same code as `salsa run` (its output folder, resume, plots, --isolate's processes).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace salsa {
class PluginHost;
}

namespace salsa::cli {

/// What `salsa ARGS...` does: argv[0] is the program's name, argv[1] the command. Returns the exit
/// status; prints errors as the program does.
int run_command(int argc, char** argv);

struct Embedding {
  /// Loads `host` in place of the program's own plugin search (the embedding program knows where its
  /// plugins are, and adds the behaviors it defines); `extra` are --plugin-dir's folders, searched first.
  std::function<void(PluginHost& host, const std::vector<std::filesystem::path>& extra)> load;
  /// The command that starts this program again (--isolate's children), before "run ...".
  std::vector<std::string> command;
};
/// Set once, before run_command, by an embedding program; empty in the salsa program.
Embedding& embedding();

}  // namespace salsa::cli
