#include "salsa/core/plugin_host.hpp"

#include <boost/dll/shared_library.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace salsa {

struct Library {
  boost::dll::shared_library handle;
  PluginInfo info;
};

template <class Base>
const PluginInfo& Entry<Base>::plugin() const {
  return library->info;
}
template struct Entry<Behavior>;
template struct Entry<TargetKind>;
template struct Entry<MapGenerator>;
template struct Entry<ContactHandler>;

namespace {

bool has_elf_header(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  return in && magic[0] == 0x7f && magic[1] == 'E' && magic[2] == 'L' && magic[3] == 'F';
}

fs::path executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path{} : exe.parent_path();
}

template <class Base>
std::string known_names(const std::vector<Entry<Base>>& entries) {
  std::string out;
  for (const auto& e : entries) out += (out.empty() ? "" : ", ") + e.factory.name;
  return out.empty() ? "none loaded" : out;
}

template <class Base>
const Entry<Base>& find(const std::vector<Entry<Base>>& entries, const std::string& name, PluginKind kind) {
  for (const auto& e : entries)
    if (e.factory.name == name) return e;
  throw UnknownPlugin(std::string("unknown ") + to_string(kind) + " '" + name + "' (known: " + known_names(entries) + ")");
}

}  // namespace

// Collects one library's registrations; commits them only if the whole registration succeeded.
class PluginHost::Collector final : public Registrar {
 public:
  std::vector<Factory<Behavior>> behaviors;
  std::vector<Factory<TargetKind>> targets;
  std::vector<Factory<MapGenerator>> maps;
  std::vector<Factory<ContactHandler>> handlers;
  void add(Factory<Behavior> f) override { behaviors.push_back(std::move(f)); }
  void add(Factory<TargetKind> f) override { targets.push_back(std::move(f)); }
  void add(Factory<MapGenerator> f) override { maps.push_back(std::move(f)); }
  void add(Factory<ContactHandler> f) override { handlers.push_back(std::move(f)); }
};

PluginHost::PluginHost() = default;

PluginHost::~PluginHost() {
  // Factories hold code from their libraries: drop them before the libraries.
  behaviors_.clear();
  targets_.clear();
  maps_.clear();
  handlers_.clear();
}

std::vector<SearchDir> PluginHost::default_search_path(const std::vector<fs::path>& extra) {
  std::vector<SearchDir> dirs;
  for (const auto& d : extra) dirs.push_back({d, "--plugin-dir"});
  if (const char* env = std::getenv("SALSA_PLUGIN_PATH")) {
    std::stringstream list(env);
    for (std::string d; std::getline(list, d, ':');)
      if (!d.empty()) dirs.push_back({d, "SALSA_PLUGIN_PATH"});
  }
  if (const char* home = std::getenv("HOME")) dirs.push_back({fs::path(home) / ".local/share/salsa/plugins", "user"});
  // The build tree has the install layout, so one rule finds both.
  if (const fs::path bin = executable_dir(); !bin.empty())
    dirs.push_back({(bin.parent_path() / SALSA_LIBDIR / "salsa/plugins").lexically_normal(),
                    fs::exists(bin.parent_path() / "CMakeCache.txt") ? "build tree" : "install"});
  return dirs;
}

void PluginHost::load(const std::vector<SearchDir>& dirs) {
  for (const auto& dir : dirs) {
    searched_.push_back(dir);
    std::error_code ec;
    if (!fs::is_directory(dir.path, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& item : fs::directory_iterator(dir.path, ec))
      if (item.path().extension() == ".so" && !fs::is_directory(item.path())) files.push_back(item.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) load_file(f);
  }
}

bool PluginHost::load_file(const fs::path& file) {
  auto fail = [&](std::string reason) {
    failures_.push_back({file, std::move(reason)});
    return false;
  };
  if (!has_elf_header(file)) return fail("not a shared library (no ELF header)");

  auto lib = std::make_shared<Library>();
  try {
    lib->handle.load(file, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    return fail(std::string("cannot be loaded: ") + e.what());
  }
  if (!lib->handle.has(entry_symbol))
    return fail(std::string("no entry point '") + entry_symbol + "' (not a salsa plugin: register with SALSA_BEHAVIOR and friends)");

  // The handshake: read the fields every ABI version keeps in place before anything else.
  const PluginDescriptor* d = lib->handle.get<const PluginDescriptor*()>(entry_symbol)();
  if (!d) return fail("entry point returned no descriptor");
  if (d->abi_version != abi_version)
    return fail("built for salsa ABI " + std::to_string(d->abi_version) + ", this is " + std::to_string(abi_version));
  if (d->descriptor_size != sizeof(PluginDescriptor) || d->descriptor_align != alignof(PluginDescriptor))
    return fail("descriptor is " + std::to_string(d->descriptor_size) + " bytes aligned to " +
                std::to_string(d->descriptor_align) + ", expected " + std::to_string(sizeof(PluginDescriptor)) +
                " aligned to " + std::to_string(alignof(PluginDescriptor)));
  if (d->toolchain != toolchain_tag())
    return fail("built with an incompatible C++ standard library (toolchain tag " + std::to_string(d->toolchain) +
                ", expected " + std::to_string(toolchain_tag()) + ")");
  lib->info = {file, d->name, d->version, d->author, d->brief};

  Collector found;
  try {
    d->register_all(found);
  } catch (const std::exception& e) {
    return fail(std::string("registration threw: ") + e.what());
  } catch (...) {
    return fail("registration threw an unknown exception");
  }

  // Duplicates: the first file wins; the later one is refused whole, naming both.
  auto clash = [&](const auto& existing, const auto& added, PluginKind kind) -> std::string {
    for (const auto& f : added)
      for (const auto& e : existing)
        if (e.factory.name == f.name)
          return std::string(to_string(kind)) + " '" + f.name + "' is already provided by " + e.plugin().file.string();
    return {};
  };
  for (const std::string& why : {clash(behaviors_, found.behaviors, PluginKind::behavior),
                                 clash(targets_, found.targets, PluginKind::target),
                                 clash(maps_, found.maps, PluginKind::map),
                                 clash(handlers_, found.handlers, PluginKind::contact_handler)})
    if (!why.empty()) return fail("duplicate: " + why);

  std::shared_ptr<const Library> shared = lib;
  for (auto& f : found.behaviors) behaviors_.push_back({shared, std::move(f)});
  for (auto& f : found.targets) targets_.push_back({shared, std::move(f)});
  for (auto& f : found.maps) maps_.push_back({shared, std::move(f)});
  for (auto& f : found.handlers) handlers_.push_back({shared, std::move(f)});
  libraries_.push_back(shared);
  return true;
}

std::vector<const PluginInfo*> PluginHost::plugins() const {
  std::vector<const PluginInfo*> out;
  for (const auto& l : libraries_) out.push_back(&l->info);
  return out;
}

const Entry<Behavior>& PluginHost::behavior(const std::string& name) const {
  return find(behaviors_, name, PluginKind::behavior);
}
const Entry<TargetKind>& PluginHost::target_kind(const std::string& name) const {
  return find(targets_, name, PluginKind::target);
}
const Entry<MapGenerator>& PluginHost::map(const std::string& name) const { return find(maps_, name, PluginKind::map); }
const Entry<ContactHandler>& PluginHost::contact_handler(const std::string& name) const {
  return find(handlers_, name, PluginKind::contact_handler);
}

template <class Base>
std::shared_ptr<Base> PluginHost::create(const Entry<Base>& entry, const ParameterValues& values) {
  try {
    std::unique_ptr<Base> object = entry.factory.create();
    object->set_parameters(values);
    // The deleter holds the library: it is unloaded only after the object is gone.
    return std::shared_ptr<Base>(object.release(), [library = entry.library](Base* p) { delete p; });
  } catch (const std::exception& e) {
    throw std::runtime_error("'" + entry.factory.name + "' (" + entry.plugin().file.string() + "): " + e.what());
  }
}
template std::shared_ptr<Behavior> PluginHost::create(const Entry<Behavior>&, const ParameterValues&);
template std::shared_ptr<TargetKind> PluginHost::create(const Entry<TargetKind>&, const ParameterValues&);
template std::shared_ptr<MapGenerator> PluginHost::create(const Entry<MapGenerator>&, const ParameterValues&);
template std::shared_ptr<ContactHandler> PluginHost::create(const Entry<ContactHandler>&, const ParameterValues&);

}  // namespace salsa
