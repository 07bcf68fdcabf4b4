// PluginHost: the folders searched, a plugin file loaded and its registrations admitted, the registries' lookups, creation.
#include "salsa/core/plugins/plugin_host.hpp"

#include <boost/dll/shared_library.hpp>
#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "plugins/loading.hpp"

namespace salsa {

using detail::current_exception_text;
using detail::dlopen_problem;
using detail::errno_text;
using detail::identifier_like;
using detail::name_rule;
using detail::one_line;
using detail::open_with_initialisers;
using detail::parameters_problem;
using detail::probe_initialisers;
using detail::shown;
using detail::Snapshot;
using detail::toolchain_difference;

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
template struct Entry<Metric>;
template struct Entry<WindField>;

namespace {

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

/// The file load() staged and probed, handed to load_file (which stages and probes a file by itself
/// otherwise): PluginHost's header, included nearly everywhere, keeps its one way to load a file.
thread_local detail::StagedFile* handed_over = nullptr;

template <class Base>
const Entry<Base>& find(const std::vector<Entry<Base>>& entries, const std::string& name, PluginKind kind) {
  for (const auto& e : entries)
    if (e.factory.name == name) return e;
  throw UnknownPlugin(std::string("unknown ") + to_string(kind) + " '" + name + "' (known: " + known_names(entries) + ")");
}

}  // namespace

// Collects one library's registrations; they are admitted one by one once all ran.
class PluginHost::Collector final : public Registrar {
 public:
  std::vector<Factory<Behavior>> behaviors;
  std::vector<Factory<TargetKind>> targets;
  std::vector<Factory<MapGenerator>> maps;
  std::vector<Factory<ContactHandler>> handlers;
  std::vector<Factory<Metric>> metrics;
  std::vector<Factory<WindField>> winds;
  void add(Factory<Behavior> f) override { behaviors.push_back(std::move(f)); }
  void add(Factory<TargetKind> f) override { targets.push_back(std::move(f)); }
  void add(Factory<MapGenerator> f) override { maps.push_back(std::move(f)); }
  void add(Factory<ContactHandler> f) override { handlers.push_back(std::move(f)); }
  void add(Factory<Metric> f) override { metrics.push_back(std::move(f)); }
  void add(Factory<WindField> f) override { winds.push_back(std::move(f)); }
};

PluginHost::PluginHost() = default;

PluginHost::~PluginHost() {
  // Factories hold code from their libraries: drop them before the libraries.
  behaviors_.clear();
  targets_.clear();
  maps_.clear();
  handlers_.clear();
  metrics_.clear();
  winds_.clear();
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
  if (const fs::path bin = executable_dir(); !bin.empty()) {
    std::error_code ec;
    dirs.push_back({(bin.parent_path() / SALSA_LIBDIR / "salsa/plugins").lexically_normal(),
                    fs::exists(bin.parent_path() / "CMakeCache.txt", ec) ? "build tree" : "install"});
  }
  return dirs;
}

void PluginHost::load(const std::vector<SearchDir>& dirs) {
  // The same file twice in one search (a folder listed twice, a link beside its target) loads once.
  // Only within one search: a later load() of a rebuilt file at the same path is a new library.
  std::vector<fs::path> seen;
  auto seen_before = [&](const fs::path& file) {
    std::error_code ec;
    const bool before = std::any_of(seen.begin(), seen.end(), [&](const fs::path& s) { return fs::equivalent(s, file, ec); });
    seen.push_back(file);
    return before;
  };
  for (const auto& dir : dirs) {
    searched_.push_back(dir);
    // Non-throwing calls only: one bad folder or entry is reported, the rest still load.
    std::error_code ec;
    const fs::file_status st = fs::status(dir.path, ec);
    if (st.type() == fs::file_type::not_found) {
      // An absent default folder is normal (`salsa plugins` shows it); one the user named is a typo.
      if (dir.origin == "--plugin-dir") failures_.push_back({dir.path, "no such plugin folder", {}});
      continue;
    }
    if (ec || !fs::is_directory(st)) {
      failures_.push_back(
          {dir.path, ec ? "plugin folder cannot be read: " + errno_text(ec.value()) : "a file, not a plugin folder", {}});
      continue;
    }
    std::vector<fs::path> files;
    fs::directory_iterator it(dir.path, ec);
    for (const fs::directory_iterator end; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".so") files.push_back(it->path());
    if (ec) failures_.push_back({dir.path, "plugin folder cannot be listed: " + errno_text(ec.value()), {}});
    std::sort(files.begin(), files.end());
    // The folder's files staged, their static initialisers probed together (one child process), then
    // each loaded by load_file.
    std::vector<detail::StagedFile> staged;
    for (const auto& f : files)
      if (!seen_before(f)) staged.push_back(detail::stage(f));
    std::vector<detail::StagedFile*> probed;
    std::vector<fs::path> copies;
    for (auto& s : staged)
      if (s.why.empty()) probed.push_back(&s), copies.push_back(s.snapshot->copy());
    std::vector<std::string> why = probe_initialisers(copies);
    for (std::size_t k = 0; k < probed.size(); ++k) probed[k]->why = std::move(why[k]);
    for (auto& s : staged) {
      handed_over = &s;
      const struct Reset {
        ~Reset() { handed_over = nullptr; }
      } reset;
      load_file(s.file);
    }
  }
}

bool PluginHost::load_file(const fs::path& file) {
  auto fail = [&](std::string reason) {
    failures_.push_back({file, std::move(reason), {}});
    return false;
  };
  // Phase 1: the file read once, its bytes checked and written to a private copy, its static
  // initialisers probed (by load() for a whole folder); then that copy is mapped.
  detail::StagedFile own;
  detail::StagedFile& staged = handed_over && handed_over->file == file ? *handed_over : own;
  if (&staged == &own) {
    own = detail::stage(file);
    if (own.why.empty()) own.why = probe_initialisers({own.snapshot->copy()}).front();
  }
  if (!staged.why.empty()) return fail(staged.why);
  auto lib = std::make_shared<Library>();
  const std::string sha256 = staged.sha256;
  {
    // Static initialisers ran in the probe's child first, then in our first dlopen (should they throw
    // only now, this file alone is refused, but glibc keeps its loader lock: see the probe); Boost.DLL's
    // dlopen then only counts a reference.
    const std::unique_ptr<Snapshot> snapshot = std::move(staged.snapshot);
    std::string why;
    void* initialised = open_with_initialisers(snapshot->copy(), file, why);
    if (!initialised) return fail(why);
    boost::dll::fs::error_code ec;
    lib->handle.load(snapshot->copy(), boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local, ec);
    ::dlclose(initialised);  // Boost.DLL's reference keeps it loaded
    if (ec) return fail(dlopen_problem(snapshot->copy(), file));
  }  // the copy is removed here; the mapping stays
  if (!lib->handle.has(entry_symbol))
    return fail(std::string("no entry point '") + entry_symbol + "' (not a salsa plugin: register with SALSA_BEHAVIOR and friends)");

  // Phase 2, the handshake: read the fields every ABI version keeps in place before anything else.
  const PluginDescriptor* d = nullptr;
  try {
    d = lib->handle.get<const PluginDescriptor*()>(entry_symbol)();
  } catch (...) {
    return fail("entry point threw: " + current_exception_text());
  }
  if (!d) return fail("entry point returned no descriptor");
  if (d->abi_version != abi_version)
    return fail("built for salsa ABI " + std::to_string(d->abi_version) + ", this is " + std::to_string(abi_version));
  if (d->descriptor_size != sizeof(PluginDescriptor) || d->descriptor_align != alignof(PluginDescriptor))
    return fail("descriptor is " + std::to_string(d->descriptor_size) + " bytes aligned to " +
                std::to_string(d->descriptor_align) + ", expected " + std::to_string(sizeof(PluginDescriptor)) +
                " aligned to " + std::to_string(alignof(PluginDescriptor)));
  if (d->toolchain != toolchain_tag()) return fail(toolchain_difference(d->toolchain, toolchain_tag()));
  if (!d->register_all) return fail("descriptor has no registration function");
  lib->info = {file, one_line(d->name), one_line(d->version), one_line(d->author), one_line(d->brief), sha256};

  // Phase 3: registration. A throw refuses the whole file: the registrations after it never ran, so
  // what it provides would depend on their order.
  Collector found;
  try {
    d->register_all(found);
  } catch (...) {
    return fail("registration threw: " + current_exception_text());
  }

  // Phase 4: each registration on its own: valid, and its name not yet taken.
  const std::shared_ptr<const Library> shared = lib;
  const std::size_t offered = found.behaviors.size() + found.targets.size() + found.maps.size() + found.handlers.size() +
                              found.metrics.size() + found.winds.size();
  std::size_t admitted = 0;
  admit(behaviors_, found.behaviors, PluginKind::behavior, shared, admitted);
  admit(targets_, found.targets, PluginKind::target, shared, admitted);
  admit(maps_, found.maps, PluginKind::map, shared, admitted);
  admit(handlers_, found.handlers, PluginKind::contact_handler, shared, admitted);
  admit(metrics_, found.metrics, PluginKind::metric, shared, admitted);
  admit(winds_, found.winds, PluginKind::wind, shared, admitted);
  if (offered > 0 && admitted == 0) return false;  // every registration refused and reported: unload it
  libraries_.push_back(shared);
  return true;
}

template <class Base>
void PluginHost::admit(std::vector<Entry<Base>>& registry, std::vector<Factory<Base>>& found, PluginKind kind,
                       const std::shared_ptr<const Library>& library, std::size_t& admitted) {
  const fs::path& file = library->info.file;
  std::vector<std::string> names;  // this file's names so far, admitted or not
  for (Factory<Base>& f : found) {
    const std::string label = std::string(to_string(kind)) + (identifier_like(f.name) ? " '" + f.name + "'" : " " + shown(f.name));
    std::string why;
    if (!identifier_like(f.name)) why = "not a valid name: " + name_rule();
    else if (std::find(names.begin(), names.end(), f.name) != names.end())
      why = "registered twice in this file (the first registration is kept)";
    else if (!f.create) why = "has no factory function";
    else if (std::string p = parameters_problem(f.parameters); !p.empty()) why = p;
    else
      for (const auto& e : registry)
        if (e.factory.name == f.name) {
          why = "the name is taken by " + e.plugin().file.string() + " (the file found first wins)";
          break;
        }
    names.push_back(f.name);
    if (!why.empty()) {
      failures_.push_back({file, label + " not registered: " + why, label});
      continue;
    }
    registry.push_back({library, std::move(f)});
    ++admitted;
  }
}

void PluginHost::add_behavior(Factory<Behavior> f, const std::string& origin) {
  const std::string label = "behavior" + (identifier_like(f.name) ? " '" + f.name + "'" : " " + shown(f.name));
  std::string why;
  if (!identifier_like(f.name)) why = "not a valid name: " + name_rule();
  else if (!f.create) why = "has no factory function";
  else if (std::string p = parameters_problem(f.parameters); !p.empty()) why = p;
  if (!why.empty()) throw std::invalid_argument(label + " not registered: " + why);
  auto lib = std::make_shared<Library>();  // no file: its handle stays empty
  lib->info = {origin, one_line(f.name.c_str()), "", "", one_line(f.brief.c_str()), ""};
  for (auto& e : behaviors_) {
    if (e.factory.name != f.name) continue;
    if (e.library->handle.is_loaded())
      throw std::invalid_argument(label + " not registered: the name is taken by " + e.plugin().file.string());
    e = {lib, std::move(f)};
    return;
  }
  behaviors_.push_back({lib, std::move(f)});
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
const Entry<Metric>& PluginHost::metric(const std::string& name) const { return find(metrics_, name, PluginKind::metric); }
const Entry<WindField>& PluginHost::wind(const std::string& name) const { return find(winds_, name, PluginKind::wind); }

template <class Base>
std::shared_ptr<Base> PluginHost::create(const Entry<Base>& entry, const ParameterValues& values) {
  try {
    std::unique_ptr<Base> object = entry.factory.create();
    if (!object) throw std::runtime_error("the factory made no object");
    object->set_parameters(values);
    // The deleter holds the library: it is unloaded only after the object is gone.
    return std::shared_ptr<Base>(object.release(), [library = entry.library](Base* p) { delete p; });
  } catch (...) {
    throw std::runtime_error("'" + entry.factory.name + "' (" + entry.plugin().file.string() + "): " +
                             current_exception_text());
  }
}
template std::shared_ptr<Behavior> PluginHost::create(const Entry<Behavior>&, const ParameterValues&);
template std::shared_ptr<TargetKind> PluginHost::create(const Entry<TargetKind>&, const ParameterValues&);
template std::shared_ptr<MapGenerator> PluginHost::create(const Entry<MapGenerator>&, const ParameterValues&);
template std::shared_ptr<ContactHandler> PluginHost::create(const Entry<ContactHandler>&, const ParameterValues&);
template std::shared_ptr<Metric> PluginHost::create(const Entry<Metric>&, const ParameterValues&);
template std::shared_ptr<WindField> PluginHost::create(const Entry<WindField>&, const ParameterValues&);

}  // namespace salsa
