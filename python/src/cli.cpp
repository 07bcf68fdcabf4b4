// salsa._core._cli: the salsa command run in this process with the behaviors registered from Python
// (python/salsa/_program.py makes a process of it), so that a queue naming them runs through the
// program's own code: its output folder, resume, summary, plots, and --isolate's processes.
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "bindings.hpp"
#include "embed.hpp"

namespace salsa::python {

namespace {

int cli(const std::vector<std::string>& again, std::vector<std::string> args) {
  cli::Embedding& embedding = cli::embedding();
  embedding.command = again;
  embedding.load = [](PluginHost& host, const std::vector<std::filesystem::path>& extra) {
    host.load(plugin_search_path(extra));
    py::gil_scoped_acquire gil;  // the factories hold Python objects
    add_python_behaviors(host);
  };
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  py::gil_scoped_release free;  // the behaviors take the GIL when they decide
  return cli::run_command(static_cast<int>(args.size()), argv.data());
}

}  // namespace

void bind_cli(py::module_& m) {
  m.def("_cli", &cli, py::arg("again"), py::arg("args"),
        "The salsa command with args (args[0] the program's name): its exit status. `again` starts this "
        "process again (--isolate's children). For python -m salsa._program only: it installs signal handlers.");
}

}  // namespace salsa::python
