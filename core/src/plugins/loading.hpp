#pragma once
// Loading one plugin file in pieces (refusals.cpp, plugin_file.cpp, initialisers.cpp) for PluginHost. Internal to libsalsa.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/plugins/plugin_host.hpp"

namespace salsa::detail {

// ---- Words for errors, and the rules a registration meets (refusals.cpp)

std::string errno_text(int error);
/// Text a plugin hands over, on one line and never null.
std::string one_line(const char* text);
/// A name as the user should see it: control characters replaced, cut when very long.
std::string shown(std::string_view name);
/// What the exception being handled says; call only inside a catch block.
std::string current_exception_text();
/// Plugin and parameter names appear in JSON, CSV headers and folder names: one simple rule.
bool identifier_like(std::string_view name);
std::string name_rule();
/// What is wrong with a declared parameter list, or empty: the same rules a user's JSON meets, so
/// the resolved test (config.json) always reads back and reruns the same.
std::string parameters_problem(const Parameters& params);
/// The toolchain tag of registry.hpp in words: which of its facts differ between plugin and host.
std::string toolchain_difference(std::uint32_t theirs, std::uint32_t ours);

// ---- Plugin files: what is found in a folder, and the private copy that is loaded (plugin_file.cpp)

/// Why the folder entry `file` cannot be a plugin (a loop, a broken link, a folder), or empty.
std::string entry_problem(const fs::path& file);
/// SHA-256 of `bytes`, as 64 lowercase hex digits (OpenSSL's libcrypto).
std::string sha256_hex(const std::vector<unsigned char>& bytes);
/// The whole file, read once through one descriptor, or why not. O_NONBLOCK: a file swapped for a
/// pipe after entry_problem() looked must not block the loader.
std::string read_whole(const fs::path& file, std::vector<unsigned char>& out);

/// A private copy of a plugin file in a fresh folder of its own (mkdtemp, locked while it exists):
/// nobody else writes it, so what was checked is what gets mapped. The destructor removes copy and
/// folder; call it right after dlopen (the mapping outlives the file).
class Snapshot {
 public:
  Snapshot() = default;
  Snapshot(const Snapshot&) = delete;
  Snapshot& operator=(const Snapshot&) = delete;
  ~Snapshot();

  /// Writes `bytes` as a copy named like `original`; empty on success, else why not.
  std::string make(const fs::path& original, const std::vector<unsigned char>& bytes);
  const fs::path& copy() const { return copy_; }

 private:
  fs::path folder_, copy_;
  int lock_ = -1;
};

/// A plugin file read once, its bytes checked (entry, ELF) and written to a private copy, waiting for
/// its static initialisers' probe; or why not.
struct StagedFile {
  fs::path file;  ///< as found in the plugin folder
  std::string sha256;
  std::unique_ptr<Snapshot> snapshot;  ///< the copy, while it waits
  std::string why;                     ///< the refusal: it could not be staged, or its probe refused it
};
StagedFile stage(const fs::path& file);

/// dlopen's complaint about the copy, said about the original.
std::string dlopen_problem(const fs::path& copy, const fs::path& original);

// ---- Static initialisers: run first in a child process, then in salsa's own (initialisers.cpp)

/// Runs `file`'s static initialisers (dlopen) under a LoadingGuard; a throw is reported as the reason
/// the file is refused. Returns the handle (close it once Boost.DLL holds its own), or null with `why`.
void* open_with_initialisers(const fs::path& file, const fs::path& original, std::string& why);
/// Why each copy's static initialisers cannot run (threw, exit, crash), found in child processes that
/// open the copies in order (one child unless a file ends it); empty when they ran, or when no child
/// could tell within a minute (the load then goes on as without it).
std::vector<std::string> probe_initialisers(const std::vector<fs::path>& copies);

}  // namespace salsa::detail
