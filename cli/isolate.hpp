#pragma once
// --isolate: the process supervisor. Each test runs in a child process (salsa re-executes itself with
// --only NAME), so a crashing plugin fails that test only.
#include <string>
#include <utility>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::cli {

/// Runs one test in a new process (this executable, the same arguments minus --isolate, --only NAME
/// and the decide threads `threads` when not "", as this run decided them) and waits for it, passing
/// SIGINT/SIGTERM on. Returns its wait status and what it wrote on stderr (the caller prints it); a
/// child that dies without a word gets a line of ours.
std::pair<int, std::string> run_isolated(const TestSpec& test, const PluginHost& host, int argc, char** argv,
                                         const std::string& threads);

}  // namespace salsa::cli
