// A plugin file's static initialisers: run first in a child (the probe), then in salsa under a guard naming the file.
#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "plugins/loading.hpp"

namespace salsa::detail {

namespace {

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

}  // namespace

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

namespace {

// ---- The probe: static initialisers run first in a child process.
// When an exception leaves dlopen, glibc keeps its loader lock, held by the loading thread for ever:
// any other thread then hangs at its first thread_local with a destructor, or dlopen. So a file's
// static initialisers first run in a child (fork, dlopen, _exit): what they throw, exit or crash with
// there is that file's refusal, and salsa's own process never runs them. One child opens a folder's
// files in turn, saying which before each; a file that ends it is refused and a new child goes on
// after it. One fork for a folder, not one per file: a fork of a big process (the sanitizers' builds
// touch hundreds of MB) costs more than opening the files.

int probe_pipe = -1;  // the child's end: which file it opens, and why its load failed
constexpr char opening = '\x01', reason = '\x02';  // "\x01<index>\n" before each file; "\x02<why>" at the end

void probe_write(const std::string& text) {
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(probe_pipe, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}
void on_probe_exit(int status, void*) {  // first of the exit handlers: the parent's never run here
  probe_write(reason + ("called exit(" + std::to_string(status) + ") while the file was loaded"));
  ::_exit(97);
}

[[noreturn]] void run_probe(const std::vector<fs::path>& copies, std::size_t first) {
  for (int sig : load_signals) ::signal(sig, SIG_DFL);  // a crash ends the child, seen by the parent
  ::on_exit(on_probe_exit, nullptr);
  for (std::size_t k = first; k < copies.size(); ++k) {
    probe_write(opening + std::to_string(k) + "\n");
    try {
      dlopen_may_throw(copies[k].c_str(), RTLD_NOW | RTLD_LOCAL);  // dlopen's own errors: the parent's load says them
    } catch (...) {
      probe_write(reason + ("threw while the file was loaded: " + current_exception_text()));
      ::_exit(96);
    }
  }
  ::_exit(0);
}

/// One child opening copies[first..]: the index of the file it ended on (copies.size() when none), and
/// why. A child that says nothing within a minute of its last file is killed: that file, no verdict.
std::pair<std::size_t, std::string> probe_from(const std::vector<fs::path>& copies, std::size_t first) {
  const std::size_t none = copies.size();
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return {none, {}};
  std::fflush(nullptr);  // nothing buffered is written twice, should the child's exit flush it
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    probe_pipe = fds[1];
    run_probe(copies, first);
  }
  ::close(fds[1]);
  if (pid < 0) {
    ::close(fds[0]);
    return {none, {}};
  }
  std::string told;  // since the last file's start
  std::size_t at = none;  // the file the child said it opens
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
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
    // Each whole "opening" line moves `at` on and restarts the minute.
    for (std::size_t line; !told.empty() && told.front() == opening && (line = told.find('\n')) != std::string::npos;) {
      at = std::stoul(told.substr(1, line - 1));
      told.erase(0, line + 1);
      deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    }
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);  // an initialiser waiting on a lock the fork copied: no verdict
  int status = 0;
  pid_t waited;
  while ((waited = ::waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
  }
  if (timed_out) return {at, {}};
  if (!told.empty() && told.front() == reason) told.erase(0, 1);
  const std::string head = "its static initialiser ";
  if (waited < 0) return told.empty() ? std::pair{none, std::string()} : std::pair{at, head + one_line(told.c_str())};  // SIGCHLD ignored
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return {none, {}};
  if (at == none) return {none, {}};  // it ended before opening a file: no verdict on any
  if (WIFSIGNALED(status)) {
    const char* name = sigabbrev_np(WTERMSIG(status));
    return {at, head + "crashed (" + (name ? "SIG" + std::string(name) : "signal " + std::to_string(WTERMSIG(status))) +
                    ") while the file was loaded"};
  }
  if (!told.empty()) return {at, head + one_line(told.c_str())};
  return {at, head + "ended the process (_exit(" + std::to_string(WEXITSTATUS(status)) + ")) while the file was loaded"};
}

}  // namespace

std::vector<std::string> probe_initialisers(const std::vector<fs::path>& copies) {
  std::vector<std::string> why(copies.size());
  for (std::size_t first = 0; first < copies.size();) {
    auto [ended_on, told] = probe_from(copies, first);
    if (ended_on >= copies.size()) break;  // every file from `first` on opened (or no child could tell)
    why[ended_on] = std::move(told);
    first = ended_on + 1;
  }
  return why;
}

}  // namespace salsa::detail
