#pragma once
// Finds, loads and checks plugin libraries (Boost.DLL) and keeps the registries of what they provide.
// A library stays loaded while the host or any object it made is alive. Each file is checked, then
// loaded from a private copy (removed once mapped), so the original may be replaced or deleted at
// any time; hosts are independent (two hosts loading one file get two copies).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "salsa/registry.hpp"

namespace salsa {

namespace fs = std::filesystem;

struct Library;  // a loaded plugin library

struct PluginInfo {
  fs::path file;  ///< as found in the plugin folder
  std::string name, version, author, brief;
  std::string sha256;  ///< of the file's bytes as loaded: tells two builds of one version apart
};

template <class Base>
struct Entry {
  std::shared_ptr<const Library> library;  // declared first: outlives the factory's code
  Factory<Base> factory;
  const PluginInfo& plugin() const;
};

/// A refusal: a whole file (or folder), or one registration of a file whose others loaded.
struct LoadFailure {
  fs::path file;             ///< as found in the plugin folder, never the private copy
  std::string reason;        ///< one line; starts with the registration when only that one was refused
  std::string registration;  ///< e.g. "map 'forest'" when only that registration was refused, else empty
};

/// A folder searched for plugins, and why it is on the list.
struct SearchDir {
  fs::path path;
  std::string origin;  ///< "--plugin-dir", "SALSA_PLUGIN_PATH", "user", "install", "build"
};

/// Thrown for unknown names; the message lists the names that exist.
struct UnknownPlugin : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class PluginHost {
 public:
  PluginHost();
  ~PluginHost();
  PluginHost(const PluginHost&) = delete;
  PluginHost& operator=(const PluginHost&) = delete;

  /// The discovery order (docs/plugins.md): the given folders, $SALSA_PLUGIN_PATH, the user folder, the
  /// install folder and, when run from a build tree, its plugins folder.
  static std::vector<SearchDir> default_search_path(const std::vector<fs::path>& extra = {});

  /// Loads every `*.so` entry of each folder (sorted by file name); failures are recorded, never
  /// thrown. A name already registered stays with the file loaded first (folder order, then file
  /// name); a later registration of it is refused alone, the rest of its file loads.
  void load(const std::vector<SearchDir>& dirs);
  /// Loads one file; false (and a recorded failure) when the whole file is refused.
  bool load_file(const fs::path& file);

  /// Registers a behavior made in this process rather than loaded from a file (a Python class,
  /// docs/python.md); `origin` stands where a plugin's file does in messages ("Python class
  /// behaviors.PyFlocking"). Refused with std::invalid_argument (one line) for what refuses a plugin's
  /// registration, and for a name a plugin file registered; one added here before under the same name
  /// is replaced (objects it made live on).
  void add_behavior(Factory<Behavior> factory, const std::string& origin);

  const std::vector<SearchDir>& searched() const { return searched_; }
  const std::vector<LoadFailure>& failures() const { return failures_; }
  std::vector<const PluginInfo*> plugins() const;

  const std::vector<Entry<Behavior>>& behaviors() const { return behaviors_; }
  const std::vector<Entry<TargetKind>>& target_kinds() const { return targets_; }
  const std::vector<Entry<MapGenerator>>& maps() const { return maps_; }
  const std::vector<Entry<ContactHandler>>& contact_handlers() const { return handlers_; }
  const std::vector<Entry<Metric>>& metrics() const { return metrics_; }
  const std::vector<Entry<WindField>>& winds() const { return winds_; }

  /// The entry of that name, or UnknownPlugin naming what exists.
  const Entry<Behavior>& behavior(const std::string& name) const;
  const Entry<TargetKind>& target_kind(const std::string& name) const;
  const Entry<MapGenerator>& map(const std::string& name) const;
  const Entry<ContactHandler>& contact_handler(const std::string& name) const;
  const Entry<Metric>& metric(const std::string& name) const;
  const Entry<WindField>& wind(const std::string& name) const;

  /// A new object from a factory, configured with `values`; it keeps its library loaded. Whatever
  /// plugin code throws (std::bad_alloc, non-std types) comes back as std::runtime_error naming the
  /// registration and its file.
  template <class Base>
  static std::shared_ptr<Base> create(const Entry<Base>& entry, const ParameterValues& values);

 private:
  class Collector;
  template <class Base>
  void admit(std::vector<Entry<Base>>& registry, std::vector<Factory<Base>>& found, PluginKind kind,
             const std::shared_ptr<const Library>& library, std::size_t& admitted);
  std::vector<SearchDir> searched_;
  std::vector<LoadFailure> failures_;
  std::vector<std::shared_ptr<const Library>> libraries_;
  std::vector<Entry<Behavior>> behaviors_;
  std::vector<Entry<TargetKind>> targets_;
  std::vector<Entry<MapGenerator>> maps_;
  std::vector<Entry<ContactHandler>> handlers_;
  std::vector<Entry<Metric>> metrics_;
  std::vector<Entry<WindField>> winds_;
};

}  // namespace salsa
