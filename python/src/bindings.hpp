#pragma once
// What the two halves of the extension module salsa._core share: the process's plugin host and the
// build tree the module sits in (docs/python.md).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <string>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/run/session.hpp"

namespace salsa::python {

namespace py = pybind11;

/// The plugins every Session of this process uses, loaded on first use as the CLI loads them:
/// $SALSA_PLUGIN_PATH, the user folder, then the build tree's plugin folder when the module is in one.
/// Each file refused is a RuntimeWarning, as the CLI's "salsa: warning: plugin ..." lines.
std::shared_ptr<const PluginHost> shared_host();
/// The same host, to register Python behaviors in (behavior.cpp): only while no Session steps, as a
/// stepping Session reads it without the GIL.
PluginHost& plugin_host();
/// The plugin folders the module searches, as the CLI's order has them, `extra` first (--plugin-dir).
std::vector<SearchDir> plugin_search_path(const std::vector<std::filesystem::path>& extra = {});
/// Adds every behavior registered from Python in this process to `host` (behavior.cpp): the salsa
/// command run in this process (cli.cpp) knows them as a Session does.
void add_python_behaviors(PluginHost& host);
/// How many Sessions are stepping now (the GIL released), in any thread.
std::atomic<int>& sessions_stepping();

/// <build> when the module is <build>/python/salsa/_core*.so of a CMake build tree, else empty.
std::filesystem::path build_tree();
/// The install prefix when the module is installed (<prefix>/lib/python3/dist-packages/salsa/_core*.so
/// beside <prefix>/bin/salsa, as the .deb puts them), else empty.
std::filesystem::path install_prefix();

/// salsa::InputError raises salsa.InputError and salsa::TestFailure salsa.TestFailure (module.cpp), each
/// with the message as the CLI prints it: on one line (line breaks a plugin passed on become spaces).
std::string one_line(std::string text);

/// salsa._core.Session (session.cpp).
void bind_session(py::module_& m);
/// The session now as the desktop draws it: an (height, width, 3) uint8 RGB array (render.cpp; built with
/// the desktop's drawing, salsa_frame).
py::array render_session(const Session& session, int width, int height);

/// salsa._core.validate_file and validate_json, salsa.validate's checks (validate.cpp).
void bind_validate(py::module_& m);
/// salsa._core.BatchRng, register_behavior and _behaviors: behaviors written in Python (behavior.cpp).
void bind_behavior(py::module_& m);
/// salsa._core._cli: the salsa command in this process, with the Python behaviors (cli.cpp).
void bind_cli(py::module_& m);
/// salsa._core._nearest: each row's k nearest items, for salsa.Env's features (features.cpp).
void bind_features(py::module_& m);

}  // namespace salsa::python
