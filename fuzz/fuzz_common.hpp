#pragma once
// Shared by the libFuzzer targets: the built-in plugins, loaded once from $SALSA_FUZZ_PLUGIN_DIR (by
// default the build's plugin folder, fuzz/CMakeLists.txt), and
// the rule every answer to bad input keeps (InputError: one line of sane length). Anything else
// thrown, a crash, a hang or a broken rule is a finding.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa_fuzz {

inline const salsa::PluginHost& host() {
  static const salsa::PluginHost* const loaded = [] {
    const char* dir = std::getenv("SALSA_FUZZ_PLUGIN_DIR");
#ifdef SALSA_FUZZ_PLUGIN_DIR
    if (!dir || !*dir) dir = SALSA_FUZZ_PLUGIN_DIR;
#endif
    if (!dir || !*dir) {
      std::fprintf(stderr, "set SALSA_FUZZ_PLUGIN_DIR to the build's plugin folder (build/.../lib/salsa/plugins)\n");
      std::abort();
    }
    auto* h = new salsa::PluginHost;
    h->load({{dir, "fuzz"}});
    for (const auto& f : h->failures()) std::fprintf(stderr, "plugin %s refused: %s\n", f.file.c_str(), f.reason.c_str());
    if (!h->failures().empty() || h->plugins().empty()) std::abort();
    return h;
  }();
  return *loaded;
}

/// A bad-input message must be one line (no control characters) and short enough to read.
inline void check_message(const salsa::InputError& e) {
  const std::string m = e.what();
  if (m.empty() || m.size() > 2000) std::abort();
  for (char c : m)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) std::abort();
}

/// A private folder for files the readers need a path for, removed at exit.
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "salsa-fuzz-XXXXXX").string();
    if (!mkdtemp(pattern.data())) std::abort();
    std::atexit([] { std::filesystem::remove_all(scratch()); });
    return std::filesystem::path(pattern);
  }();
  return dir;
}

inline std::filesystem::path write(const std::string& name, const uint8_t* data, size_t size) {
  const std::filesystem::path file = scratch() / name;
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

}  // namespace salsa_fuzz
