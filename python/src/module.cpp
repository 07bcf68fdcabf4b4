// salsa._core: the extension module under the salsa package (python/salsa/). Loads the plugins the way
// the CLI does, raises the core's one-line errors as Python exceptions and binds the Session.
#include <dlfcn.h>

#include <system_error>
#include <vector>

#include "bindings.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/model/drone_config.hpp"
#include "salsa/core/run/session.hpp"

namespace salsa::python {

namespace fs = std::filesystem;

namespace {

/// The module's own file, found through the loader: python, not salsa, is the running program.
fs::path module_file() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<const void*>(&module_file), &info) == 0 || !info.dli_fname) return {};
  std::error_code ec;
  const fs::path file = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path{} : file;
}

}  // namespace

std::vector<SearchDir> plugin_search_path(const std::vector<fs::path>& extra) {
  std::vector<SearchDir> dirs = PluginHost::default_search_path(extra);
  // The install or build folder the core derives from the running program is python's, not salsa's:
  // the module's own build tree instead.
  std::erase_if(dirs, [](const SearchDir& d) { return d.origin == "install" || d.origin == "build tree"; });
  if (const fs::path root = build_tree(); !root.empty())
    dirs.push_back({(root / SALSA_LIBDIR / "salsa/plugins").lexically_normal(), "build tree"});
  else if (const fs::path prefix = install_prefix(); !prefix.empty())
    dirs.push_back({(prefix / SALSA_LIBDIR / "salsa/plugins").lexically_normal(), "install"});
  return dirs;
}

fs::path build_tree() {
  const fs::path file = module_file();
  if (file.empty()) return {};
  const fs::path root = file.parent_path().parent_path().parent_path();  // <build>/python/salsa/_core.so
  std::error_code ec;
  return fs::exists(root / "CMakeCache.txt", ec) ? root : fs::path{};
}

fs::path install_prefix() {
  const fs::path file = module_file();
  if (file.empty()) return {};
  fs::path prefix = (file.parent_path() / SALSA_PYTHON_PREFIX).lexically_normal();
  if (!prefix.has_filename()) prefix = prefix.parent_path();  // "/usr/", as "../.." normalises, is "/usr"
  std::error_code ec;
  return fs::is_directory(prefix / SALSA_LIBDIR / "salsa/plugins", ec) ? prefix : fs::path{};
}

namespace {
std::shared_ptr<PluginHost> host;  // guarded by the GIL: every caller holds it
}  // namespace

PluginHost& plugin_host() {
  shared_host();
  return *host;
}

std::atomic<int>& sessions_stepping() {
  static std::atomic<int> count{0};
  return count;
}

std::shared_ptr<const PluginHost> shared_host() {
  if (host) return host;
  auto loaded = std::make_shared<PluginHost>();
  loaded->load(plugin_search_path());
  host = loaded;
  for (const LoadFailure& f : loaded->failures()) {
    const std::string line = "plugin " + f.file.string() + (f.registration.empty() ? " skipped: " : ": ") + f.reason;
    if (PyErr_WarnEx(PyExc_RuntimeWarning, one_line(line).c_str(), 1) != 0) throw py::error_already_set();
  }
  return host;
}

std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

}  // namespace salsa::python

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  using namespace salsa::python;
  m.doc() = "salsa's core (libsalsa) for Python: import the salsa package, not this module.";
  // Never destroyed: a static py::object would outlive the interpreter at exit.
  static auto* input_error = new py::exception<salsa::InputError>(m, "InputError", PyExc_Exception);
  static auto* test_failure = new py::exception<salsa::TestFailure>(m, "TestFailure", PyExc_RuntimeError);
  input_error->attr("__doc__") =
      "Bad input: a test file or dict, a folder that is not salsa output, a salsa run refused. The message is "
      "the CLI's line without its 'salsa: ' prefix: the file, the field, the value and what is allowed.";
  test_failure->attr("__doc__") =
      "A test failed while it ran (a plugin or metric threw): one line naming the test, the plugin and the time.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const salsa::InputError& e) {
      PyErr_SetString(input_error->ptr(), one_line(e.what()).c_str());
    } catch (const salsa::TestFailure& e) {
      PyErr_SetString(test_failure->ptr(), one_line(e.what()).c_str());
    }
  });
  m.def(
      "build_tree",
      []() -> py::object {
        const std::filesystem::path root = build_tree();
        return root.empty() ? py::object(py::none()) : py::object(py::str(root.string()));
      },
      "The CMake build tree this module was built in (it holds bin/salsa and the plugins), or None.");
  m.def(
      "install_prefix",
      []() -> py::object {
        const std::filesystem::path prefix = install_prefix();
        return prefix.empty() ? py::object(py::none()) : py::object(py::str(prefix.string()));
      },
      "The install prefix (it holds bin/salsa and the plugins) when the module is installed, or None.");
  m.def(
      "plugin_folders",
      []() {
        py::list out;
        for (const salsa::SearchDir& d : shared_host()->searched()) out.append(py::make_tuple(d.path.string(), d.origin));
        return out;
      },
      "The folders searched for plugins, in order, as (path, origin) pairs (loads the plugins first).");
  m.def(
      "declared_columns",
      [] {
        py::dict out;
        for (const salsa::StateColumn& c : salsa::declared_drone_columns())
          out[py::str(std::string(c.name))] = py::make_tuple(std::string(c.unit), c.width);
        return out;
      },
      "Every drone state column a simulation may keep: name -> (unit, width).");
  m.def(
      "input_units",
      [] {
        // The units the core and the plugins declare for a test's numbers, by their summary.csv column.
        py::dict out;
        for (const auto& f : salsa::drone_schema()) out[py::str("drone." + f.spec.name)] = f.spec.unit;
        for (const salsa::TestModel& model : salsa::test_models())
          for (const salsa::ModelField& f : model.fields) out[py::str(model.key + "." + f.spec.name)] = f.spec.unit;
        auto params = [&](const std::string& prefix, const auto& entries) {
          for (const auto& e : entries)
            for (const salsa::Parameter& p : e.factory.parameters) out[py::str(prefix + p.name)] = p.unit;
        };
        const auto host = shared_host();
        params("behavior.", host->behaviors());
        params("map.", host->maps());
        params("target.", host->target_kinds());
        params("wind.field.params.", host->winds());
        // A metric's and a contact handler's parameters are columns under their own name.
        for (const auto& e : host->metrics())
          for (const salsa::Parameter& p : e.factory.parameters) out[py::str("metric." + e.factory.name + "." + p.name)] = p.unit;
        for (const auto& e : host->contact_handlers())
          for (const salsa::Parameter& p : e.factory.parameters) out[py::str("contact_handler." + e.factory.name + "." + p.name)] = p.unit;
        return out;
      },
      "The units of a test's numbers as declared (drone.*, the models' fields, the plugins' parameters).");
  m.def("version", [] { return std::string(salsa::salsa_version()); }, "libsalsa's version, e.g. '0.1.0'.");
  bind_session(m);
  bind_validate(m);
  bind_behavior(m);
  bind_features(m);
  bind_cli(m);
}
