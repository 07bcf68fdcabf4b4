#include "salsa/core/plugins/plugin_host.hpp"

#include <boost/dll/shared_library.hpp>
#include <cxxabi.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>
#include <new>
#include <sstream>
#include <tuple>

#include <openssl/evp.h>

#include "plugins/elf_check.hpp"

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
template struct Entry<Metric>;
template struct Entry<WindField>;

namespace {

// ---- Words for errors

std::string errno_text(int error) {
  switch (error) {
    case ELOOP: return "symbolic link loop";
    case EACCES: case EPERM: return "permission denied";
    default: {
      std::string s = std::strerror(error);
      if (!s.empty()) s[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
      return s;
    }
  }
}

/// Text a plugin hands over, on one line and never null.
std::string one_line(const char* text) {
  std::string s = text ? text : "";
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return s;
}

/// A name as the user should see it: control characters replaced, cut when very long.
std::string shown(std::string_view name) {
  std::string s(name.substr(0, 60));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return '"' + s + (name.size() > 60 ? "...\"" : "\"");
}

/// The shortest text that reads back as the same double (1e-09, not 0).
std::string number(double v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

/// What the exception being handled says; call only inside a catch block.
std::string current_exception_text() {
  try {
    throw;
  } catch (const std::bad_alloc&) {
    return "out of memory (std::bad_alloc)";
  } catch (const std::exception& e) {
    return one_line(e.what());
  } catch (const char* text) {
    return one_line(text);
  } catch (...) {
    const std::type_info* type = abi::__cxa_current_exception_type();
    if (!type) return "an unknown exception";
    int status = 0;
    char* name = abi::__cxa_demangle(type->name(), nullptr, nullptr, &status);
    std::string out = "an exception of type " + std::string(status == 0 && name ? name : type->name()) +
                      " (not a std::exception)";
    std::free(name);
    return out;
  }
}

/// Plugin and parameter names appear in JSON, CSV headers and folder names: one simple rule.
constexpr std::size_t max_plugin_name = 64;
bool identifier_like(std::string_view name) {
  auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  if (name.empty() || name.size() > max_plugin_name || !letter(name.front())) return false;
  return std::all_of(name.begin(), name.end(),
                     [&](char c) { return letter(c) || (c >= '0' && c <= '9') || c == '_' || c == '-'; });
}
std::string name_rule() {
  return "a name starts with a letter and uses only letters, digits, '_' and '-', 1 to " +
         std::to_string(max_plugin_name) + " characters";
}

/// What is wrong with a declared parameter list, or empty: the same rules a user's JSON meets, so
/// the resolved test (config.json) always reads back and reruns the same.
std::string parameters_problem(const Parameters& params) {
  for (std::size_t i = 0; i < params.size(); ++i) {
    const Parameter& p = params[i];
    if (!identifier_like(p.name)) return "parameter " + shown(p.name) + ": not a valid name: " + name_rule();
    const std::string at = "parameter '" + p.name + "': ";
    for (std::size_t j = 0; j < i; ++j)
      if (params[j].name == p.name) return at + "declared twice";
    for (auto [what, v] : {std::pair{"default", p.value}, {"min", p.min}, {"max", p.max}, {"step", p.step}})
      if (!std::isfinite(v)) return at + what + " " + number(v) + " is not a finite number";
    if (p.min > p.max) return at + "min " + number(p.min) + " is greater than max " + number(p.max);
    if (p.step < 0) return at + "step " + number(p.step) + " is negative";
    if (p.value < p.min || p.value > p.max)
      return at + "default " + number(p.value) + " is outside [" + number(p.min) + ", " + number(p.max) + "]";
    if (!p.check(p.value).empty()) return at + "default " + number(p.value) + " is not a whole number (step 1)";
  }
  return {};
}

/// The toolchain tag of registry.hpp in words: which of its facts differ between plugin and host.
std::string toolchain_difference(std::uint32_t theirs, std::uint32_t ours) {
  std::vector<std::string> facts;
  if ((theirs & 1) != (ours & 1))
    facts.push_back((theirs & 1) ? "built with the new C++ ABI (_GLIBCXX_USE_CXX11_ABI=1), this salsa uses the old one"
                                 : "built with the old C++ ABI (_GLIBCXX_USE_CXX11_ABI=0), this salsa uses the new one");
  // The layout of toolchain_tag(): sizeof std::string << 16 | std::function << 8 | std::vector << 1.
  for (auto [type, shift, mask] : {std::tuple{"std::string", 16u, 0xffffu}, {"std::function", 8u, 0xffu},
                                   {"std::vector", 1u, 0x7fu}}) {
    const std::uint32_t there = theirs >> shift & mask, here = ours >> shift & mask;
    if (there != here)
      facts.push_back(std::string(type) + " is " + std::to_string(there) + " bytes there, " + std::to_string(here) + " here");
  }
  std::string out = "incompatible C++ standard library: ";
  if (facts.empty()) return out + "toolchain tag " + std::to_string(theirs) + ", expected " + std::to_string(ours);
  for (std::size_t i = 0; i < facts.size(); ++i) out += (i ? "; " : "") + facts[i];
  return out + " (rebuild it with the compiler and standard library salsa was built with)";
}

// ---- Plugin files: what is found in a folder, and the private copy that is loaded

/// Why the folder entry `file` cannot be a plugin (a loop, a broken link, a folder), or empty.
std::string entry_problem(const fs::path& file) {
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(file, ec);
  if (ec && link.type() != fs::file_type::not_found) return "cannot be read: " + errno_text(ec.value());
  if (link.type() == fs::file_type::not_found) return "no such file";
  const fs::file_status target = fs::status(file, ec);
  if (ec && ec.value() == ELOOP) return "symbolic link loop";
  if (target.type() == fs::file_type::not_found && fs::is_symlink(link)) {
    std::error_code read_ec;
    const fs::path to = fs::read_symlink(file, read_ec);
    return "broken symbolic link to " + (read_ec ? std::string("a missing file") : to.string());
  }
  if (ec) return "cannot be read: " + errno_text(ec.value());
  if (fs::is_directory(target)) return "a folder, not a shared library";
  if (!fs::is_regular_file(target)) return "not a regular file (a pipe, socket or device), not a shared library";
  return {};
}

/// SHA-256 of `bytes`, as 64 lowercase hex digits (OpenSSL's libcrypto).
std::string sha256_hex(const std::vector<unsigned char>& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &size, EVP_sha256(), nullptr) != 1) return {};
  static constexpr char hex[] = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < size; ++i) (out += hex[digest[i] >> 4]) += hex[digest[i] & 15];
  return out;
}

/// The whole file, read once through one descriptor, or why not. O_NONBLOCK: a file swapped for a
/// pipe after entry_problem() looked must not block the loader.
std::string read_whole(const fs::path& file, std::vector<unsigned char>& out) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "cannot be read: " + errno_text(errno);
  struct stat st {};
  std::string why;
  if (::fstat(fd, &st) != 0) why = "cannot be read: " + errno_text(errno);
  else if (!S_ISREG(st.st_mode)) why = "not a regular file, not a shared library";
  else {
    try {
      out.resize(static_cast<std::size_t>(st.st_size));
    } catch (const std::exception&) {
      why = "too large to load (" + std::to_string(st.st_size) + " bytes)";
    }
    std::size_t got = 0;
    while (why.empty() && got < out.size()) {
      const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) why = "cannot be read: " + errno_text(errno);
      else if (n == 0) out.resize(got);  // shrank while read: check what there is
      else got += static_cast<std::size_t>(n);
    }
  }
  ::close(fd);
  return why;
}

constexpr const char* snapshot_prefix = "salsa-plugin-";

/// Copies left by a process that died while loading (a plugin crashing in its static constructors):
/// their folder is no longer locked. Young folders are left alone: their owner may not have locked
/// them yet.
void sweep_stale_snapshots(const fs::path& tmp) {
  std::error_code ec;
  for (fs::directory_iterator it(tmp, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().filename().string().rfind(snapshot_prefix, 0) != 0) continue;
    struct stat st {};
    if (::lstat(it->path().c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::geteuid() ||
        std::time(nullptr) - st.st_mtime < 60)
      continue;
    const int fd = ::open(it->path().c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) continue;
    std::error_code remove_ec;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) fs::remove_all(it->path(), remove_ec);
    ::close(fd);
  }
}

/// A private copy of a plugin file in a fresh folder of its own (mkdtemp, locked while it exists):
/// nobody else writes it, so what was checked is what gets mapped. The destructor removes copy and
/// folder; call it right after dlopen (the mapping outlives the file).
class Snapshot {
 public:
  Snapshot() = default;
  Snapshot(const Snapshot&) = delete;
  Snapshot& operator=(const Snapshot&) = delete;
  ~Snapshot() {
    std::error_code ec;
    if (!copy_.empty()) fs::remove(copy_, ec);
    if (!folder_.empty()) fs::remove(folder_, ec);
    if (lock_ >= 0) ::close(lock_);
  }

  /// Writes `bytes` as a copy named like `original`; empty on success, else why not.
  std::string make(const fs::path& original, const std::vector<unsigned char>& bytes) {
    std::error_code ec;
    const fs::path tmp = fs::temp_directory_path(ec);
    if (ec) {
      const char* env = std::getenv("TMPDIR");
      return std::string("no temporary folder for its private copy (") + (env ? "$TMPDIR " + std::string(env) : "/tmp") +
             ": " + errno_text(ec.value()) + ")";
    }
    static std::once_flag swept;
    std::call_once(swept, [&] { sweep_stale_snapshots(tmp); });
    std::string folder = (tmp / (std::string(snapshot_prefix) + "XXXXXX")).string();
    if (!::mkdtemp(folder.data())) return "cannot make its private copy in " + tmp.string() + ": " + errno_text(errno);
    folder_ = folder;
    lock_ = ::open(folder_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (lock_ >= 0) ::flock(lock_, LOCK_EX);
    const fs::path copy = folder_ / original.filename();
    const int fd = ::open(copy.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0700);
    if (fd < 0) return "cannot make its private copy in " + tmp.string() + ": " + errno_text(errno);
    copy_ = copy;
    int error = 0;
    for (std::size_t written = 0; written < bytes.size() && !error;) {
      const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
      if (n > 0) written += static_cast<std::size_t>(n);
      else if (n == 0 || errno != EINTR) error = n == 0 ? EIO : errno;
    }
    if (::close(fd) != 0 && !error) error = errno;  // a full disk may show only here
    if (error) return "cannot make its private copy in " + tmp.string() + ": " + errno_text(error);
    return {};
  }
  const fs::path& copy() const { return copy_; }

 private:
  fs::path folder_, copy_;
  int lock_ = -1;
};

/// dlopen's complaint about the copy, said about the original.
std::string dlopen_problem(const fs::path& copy, const fs::path& original) {
  const char* raw = ::dlerror();
  std::string text = one_line(raw ? raw : "unknown dlopen error");
  for (std::size_t at; (at = text.find(copy.string())) != std::string::npos;)
    text.replace(at, copy.string().size(), original.string());
  if (text.rfind(original.string() + ": ", 0) == 0) text.erase(0, original.string().size() + 2);
  if (text.find("failed to map segment") != std::string::npos)
    text += " (is " + copy.parent_path().parent_path().string() + " mounted noexec? set TMPDIR to another folder)";
  return "cannot be loaded: " + text;
}

// ---- Static initialisers run inside dlopen, before salsa sees the file's entry point. What they do
// there is answered for the file alone: a throw refuses it (the others load); exit() or a crash ends
// the process, as plugin code may, but with a line naming the file first.

/// The line's start, prepared before dlopen so that the handlers below only write (async-signal-safe).
char loading_note[4200];
std::size_t loading_note_size = 0;
std::atomic<bool> loading{false};
constexpr int load_signals[] = {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL};
struct sigaction saved_actions[std::size(load_signals)];

void write_all(const char* text, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(STDERR_FILENO, text, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    text += n;
    size -= static_cast<std::size_t>(n);
  }
}
void write_loading_note(const char* how) {
  write_all(loading_note, loading_note_size);
  write_all(how, std::strlen(how));
}

void on_exit_while_loading() {
  if (!loading.load()) return;
  write_loading_note("called exit() while the file was loaded, ending salsa (move the file out of the plugin folder)\n");
  ::_exit(1);  // not the status the plugin chose: salsa did not finish what it was asked
}

void on_signal_while_loading(int sig) {
  const char* how = sig == SIGABRT   ? "aborted (SIGABRT) while the file was loaded (move the file out of the plugin folder)\n"
                    : sig == SIGSEGV ? "crashed (SIGSEGV) while the file was loaded (move the file out of the plugin folder)\n"
                                     : "crashed (a fatal signal) while the file was loaded (move the file out of the plugin folder)\n";
  write_loading_note(how);
  for (std::size_t i = 0; i < std::size(load_signals); ++i)  // then whatever handled it before: salsa's crash note, or death
    if (load_signals[i] == sig) ::sigaction(sig, &saved_actions[i], nullptr);
  ::raise(sig);
}

/// While alive, a static initialiser ending the process names `file` on stderr first.
class LoadingGuard {
 public:
  explicit LoadingGuard(const fs::path& file) {
    static std::once_flag hooks;
    std::call_once(hooks, [] {
      std::atexit(on_exit_while_loading);
      std::at_quick_exit(on_exit_while_loading);
    });
    std::string note = "salsa: " + file.string();
    note.resize(std::min(note.size(), sizeof loading_note - 100));
    for (char& c : note)
      if (c == '\n' || c == '\r') c = ' ';
    note += ": its static initialiser ";
    std::memcpy(loading_note, note.data(), note.size());
    loading_note_size = note.size();
    struct sigaction act {};
    act.sa_handler = on_signal_while_loading;
    act.sa_flags = SA_ONSTACK;
    sigemptyset(&act.sa_mask);
    for (std::size_t i = 0; i < std::size(load_signals); ++i) ::sigaction(load_signals[i], &act, &saved_actions[i]);
    loading.store(true);
  }
  ~LoadingGuard() {
    loading.store(false);
    for (std::size_t i = 0; i < std::size(load_signals); ++i) ::sigaction(load_signals[i], &saved_actions[i], nullptr);
  }
  LoadingGuard(const LoadingGuard&) = delete;
  LoadingGuard& operator=(const LoadingGuard&) = delete;
};

/// <dlfcn.h> declares dlopen noexcept, so a call the compiler sees may have no unwind entry: an
/// exception from a static initialiser would then end in std::terminate. Called through a pointer
/// it cannot see through, the call may throw and the exception reaches the caller's catch.
using dlopen_type = void* (*)(const char*, int);
dlopen_type volatile dlopen_may_throw = &::dlopen;

/// Runs `file`'s static initialisers (dlopen) under a LoadingGuard; a throw is reported as the reason
/// the file is refused. Returns the handle (close it once Boost.DLL holds its own), or null with `why`.
void* open_with_initialisers(const fs::path& file, const fs::path& original, std::string& why) {
  static std::mutex one_at_a_time;  // the note and the saved handlers are process-wide
  const std::lock_guard lock(one_at_a_time);
  const LoadingGuard guard(original);
  try {
    void* handle = dlopen_may_throw(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) why = dlopen_problem(file, original);
    return handle;
  } catch (...) {
    why = "its static initialiser threw while the file was loaded: " + current_exception_text();
    return nullptr;
  }
}

// ---- The probe: static initialisers run first in a child process.
// When an exception leaves dlopen, glibc keeps its loader lock, held by the loading thread for ever:
// any other thread then hangs at its first thread_local with a destructor, or dlopen. So a file's
// static initialisers first run in a child (fork, dlopen, _exit): what they throw, exit or crash with
// there is that file's refusal, and salsa's own process never runs them.

int probe_pipe = -1;  // the child's end: why its load failed

void probe_write(const std::string& text) {
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(probe_pipe, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}
void on_probe_exit(int status, void*) {  // first of the exit handlers: the parent's never run here
  const std::string text = "called exit(" + std::to_string(status) + ") while the file was loaded";
  probe_write(text);
  ::_exit(97);
}

[[noreturn]] void run_probe(const fs::path& copy) {
  for (int sig : load_signals) ::signal(sig, SIG_DFL);  // a crash ends the child, seen by the parent
  ::on_exit(on_probe_exit, nullptr);
  try {
    dlopen_may_throw(copy.c_str(), RTLD_NOW | RTLD_LOCAL);  // dlopen's own errors: the parent's load says them
  } catch (...) {
    probe_write("threw while the file was loaded: " + current_exception_text());
    ::_exit(96);
  }
  ::_exit(0);
}

/// Why `copy`'s static initialisers cannot run (threw, exit, crash), found in a child process; empty
/// when they ran, or when no child could tell within a minute (the load then goes on as without it).
std::string probe_initialisers(const fs::path& copy) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return {};
  std::fflush(nullptr);  // nothing buffered is written twice, should the child's exit flush it
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    probe_pipe = fds[1];
    run_probe(copy);
  }
  ::close(fds[1]);
  if (pid < 0) {
    ::close(fds[0]);
    return {};
  }
  std::string told;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  bool timed_out = false;
  for (std::array<char, 512> buf{};;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(left));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child is gone
    if (told.size() < 4000) told.append(buf.data(), static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);  // an initialiser waiting on a lock the fork copied: no verdict
  int status = 0;
  pid_t waited;
  while ((waited = ::waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
  }
  if (timed_out) return {};
  const std::string head = "its static initialiser ";
  if (waited < 0) return told.empty() ? "" : head + one_line(told.c_str());  // SIGCHLD ignored: what it wrote
  if (WIFSIGNALED(status)) {
    const char* name = sigabbrev_np(WTERMSIG(status));
    return head + "crashed (" + (name ? "SIG" + std::string(name) : "signal " + std::to_string(WTERMSIG(status))) +
           ") while the file was loaded";
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return {};
  if (!told.empty()) return head + one_line(told.c_str());
  return head + "ended the process (_exit(" + std::to_string(WEXITSTATUS(status)) + ")) while the file was loaded";
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
    for (const auto& f : files)
      if (!seen_before(f)) load_file(f);
  }
}

bool PluginHost::load_file(const fs::path& file) {
  auto fail = [&](std::string reason) {
    failures_.push_back({file, std::move(reason), {}});
    return false;
  };
  // Phase 1: read the file once, check the bytes, write them to a private copy and map that copy.
  if (std::string why = entry_problem(file); !why.empty()) return fail(why);
  auto lib = std::make_shared<Library>();
  std::string sha256;
  {
    std::vector<unsigned char> bytes;
    if (std::string why = read_whole(file, bytes); !why.empty()) return fail(why);
    sha256 = sha256_hex(bytes);  // of the bytes that get mapped: two builds of one version differ here
    if (std::string why = elf_problem(bytes.data(), bytes.size()); !why.empty()) return fail(why);
    Snapshot snapshot;
    if (std::string why = snapshot.make(file, bytes); !why.empty()) return fail(why);
    // Static initialisers run in the probe's child first, then in our first dlopen (should they throw
    // only now, this file alone is refused, but glibc keeps its loader lock: see the probe); Boost.DLL's
    // dlopen then only counts a reference.
    if (std::string why = probe_initialisers(snapshot.copy()); !why.empty()) return fail(why);
    std::string why;
    void* initialised = open_with_initialisers(snapshot.copy(), file, why);
    if (!initialised) return fail(why);
    boost::dll::fs::error_code ec;
    lib->handle.load(snapshot.copy(), boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local, ec);
    ::dlclose(initialised);  // Boost.DLL's reference keeps it loaded
    if (ec) return fail(dlopen_problem(snapshot.copy(), file));
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
