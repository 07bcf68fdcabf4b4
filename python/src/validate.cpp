// salsa.validate's checks (python/salsa/_validate.py): those of `salsa validate` (cli/validate.cpp), in
// this process: a map file read through the map plugin, a test or queue read, every test set up, and the
// workload warnings and the shared-state warning (a global behavior beside a radio) collected rather
// than printed.
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "bindings.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/shared_state.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/run/session.hpp"

namespace salsa::python {

namespace {

namespace fs = std::filesystem;

/// Every test set up as a run would (the plugins' data checked), and the warnings of those likely to
/// take hours. A plugin refusing its data is bad input, as for a Session.
std::vector<std::string> set_up(const Queue& queue, const PluginHost& host) {
  std::vector<std::string> warnings;
  for (const TestSpec& t : queue.tests) {
    try {
      if (std::string line = workload_warning(t, make_setup(t, host)); !line.empty()) warnings.push_back(std::move(line));
    } catch (const TestFailure& e) {
      throw InputError(e.what());
    }
  }
  if (std::string line = shared_state_warning(queue.tests, host); !line.empty()) warnings.push_back(queue.source + ": the queue " + line);
  return warnings;
}

}  // namespace

void bind_validate(py::module_& m) {
  m.def(
      "validate_file",
      [](const std::string& file) {
        const auto host = shared_host();
        py::gil_scoped_release nogil;
        if (is_map_file(file)) {
          load_map_file(file, *host);
          return std::vector<std::string>{};
        }
        return set_up(load_queue(file, *host, {}), *host);
      },
      py::arg("file"), "salsa validate FILE: the workload warnings of a test, queue or map file; InputError when bad.");
  m.def(
      "validate_json",
      [](const std::string& text, const std::string& stem) {
        const auto host = shared_host();
        py::gil_scoped_release nogil;
        return set_up(parse_queue(text, "<dict>", *host, {}, fs::current_path(), stem), *host);
      },
      py::arg("text"), py::arg("stem"),
      "salsa validate of a test or queue given as JSON text (named <dict>, its paths from the working folder).");
}

}  // namespace salsa::python
