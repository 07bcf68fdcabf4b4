// Signals: SIGINT / SIGTERM ask the run to stop; fatal signals and exit() in plugin code write the
// note prepared before each test (written by the handlers with write(2) only).
#include "salsa/core/run/signals.hpp"

#include <semaphore.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "run/running_notes.hpp"

namespace salsa {

std::atomic<int> stop_requested{0};

namespace {

RunningNote notes[max_notes];
std::atomic<bool> handlers_installed{false};
sem_t stop_posted;  // posted once by the first stop signal
std::atomic<bool> may_exit{true};  // stop_may_exit

void write_all(const char* text, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(STDERR_FILENO, text, size);
    if (n <= 0) {
      if (n < 0 && errno == EINTR) continue;
      return;
    }
    text += n, size -= static_cast<std::size_t>(n);
  }
}
void write_all(const char* text) { write_all(text, std::strlen(text)); }

const char* signal_text(int sig) {
  switch (sig) {
    case SIGSEGV: return "SIGSEGV (segmentation fault)";
    case SIGBUS: return "SIGBUS (bus error)";
    case SIGFPE: return "SIGFPE (arithmetic error)";
    case SIGILL: return "SIGILL (illegal instruction)";
    case SIGABRT: return "SIGABRT (aborted)";
    case SIGINT: return "SIGINT (interrupted)";
    case SIGTERM: return "SIGTERM (terminated)";
    case SIGKILL: return "SIGKILL (killed)";
    default: return nullptr;
  }
}

void write_number(std::uint64_t n) {
  char digits[24];
  std::size_t i = sizeof digits;
  do digits[--i] = static_cast<char>('0' + n % 10); while ((n /= 10) > 0);
  write_all(digits + i, sizeof digits - i);
}

/// "<head><event><detail> at step <n><tail>", async-signal-safe. `running` > 1 says the faulting
/// thread was not one stepping a test, so every running test is named.
void write_note(const RunningNote& note, const char* event, const char* detail, std::size_t running) {
  write_all(note.head.data(), note.head.size());
  write_all(event);
  write_all(detail);
  if (running > 1) {
    write_all(" (one of ");
    write_number(running);
    write_all(" tests running)");
  }
  write_all(" at step ");
  write_number(note.step.load(std::memory_order_relaxed));
  write_all(note.tail.data(), note.tail.size());
}

/// Writes the note of the test run by the calling thread, or else of every running test; returns
/// how many were written.
std::size_t write_notes(const char* event, const char* detail) {
  const pid_t self = ::gettid();
  std::size_t running = 0;
  for (const auto& n : notes)
    if (n.active.load(std::memory_order_acquire)) {
      if (n.thread.load(std::memory_order_relaxed) == self) {
        write_note(n, event, detail, 1);
        return 1;
      }
      ++running;
    }
  for (const auto& n : notes)
    if (n.active.load(std::memory_order_acquire)) write_note(n, event, detail, running);
  return running;
}

extern "C" void on_fatal_signal(int sig) {
  const int saved = errno;
  const char* name = signal_text(sig);
  if (write_notes("died of ", name ? name : "a fatal signal") == 0) {
    write_all("salsa: died of ");
    write_all(name ? name : "a fatal signal");
    write_all("\n");
  }
  errno = saved;
  ::signal(sig, SIG_DFL);  // SA_RESETHAND did this already; kept for clarity
  ::raise(sig);
}

extern "C" void on_stop_signal(int sig) {
  int none = 0;
  if (!stop_requested.compare_exchange_strong(none, sig)) {  // the second one: stop now
    ::signal(sig, SIG_DFL);
    ::raise(sig);
  }
  const int saved = errno;
  ::sem_post(&stop_posted);  // async-signal-safe: wakes the watchdog
  errno = saved;
}

// The run stops between steps, and one step (10^6 drones, a slow plugin) may take minutes: if the
// process still runs this long after a stop was asked, the watchdog ends it. Each running test's
// rows so far stay in its .partial folder (never published), which --resume redoes.
constexpr auto stop_grace = std::chrono::milliseconds(800);

void watchdog() {
  while (::sem_wait(&stop_posted) != 0) {
  }
  const int sig = stop_requested.load();
  std::this_thread::sleep_for(stop_grace);
  // Ends the process while a test steps, or while the front-end says nothing of value is under way
  // (its start-up); not while it writes its summaries or waits for its --isolate children.
  for (;;) {
    const bool stepping = std::any_of(std::begin(notes), std::end(notes), [](const RunningNote& n) { return n.active.load(); });
    if (stepping || may_exit.load()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const char* name = signal_text(sig);
  if (write_notes("stopped by ", name ? name : "a stop signal") == 0) {
    write_all("salsa: stopped by ");
    write_all(name ? name : "a stop signal");
    write_all(" (run again with --resume for the rest)\n");
  }
  ::_exit(128 + sig);
}

extern "C" void on_exit_mid_test() {
  if (write_notes("ended by a call to exit() in plugin code", "") > 0) ::_exit(1);
}

}  // namespace

RunningNote* prepare_note(const TestSpec& test, const PluginHost& host, const std::filesystem::path& work) {
  if (!handlers_installed.load()) return nullptr;
  static std::once_flag exit_hooks;  // registered after the plugins are loaded, so they run first at exit
  std::call_once(exit_hooks, [] {
    std::atexit(on_exit_mid_test);
    std::at_quick_exit(on_exit_mid_test);
  });
  RunningNote* note = nullptr;
  for (auto& n : notes)
    if (bool free = false; n.taken.compare_exchange_strong(free, true)) {
      note = &n;
      break;
    }
  if (!note) return nullptr;  // more tests at once than slots: the crash line names no test
  auto plugin = [](const char* kind, const std::string& name, const auto& entry) {
    return std::string(kind) + " '" + name + "' (" + entry.plugin().file.string() + ")";
  };
  std::string plugins;
  for (const GroupSpec& g : test.groups) plugins += plugin("behavior", g.behavior.name, host.behavior(g.behavior.name)) + ", ";
  plugins += plugin("map", test.map.name, host.map(test.map.name));
  if (test.targets > 0) plugins += ", " + plugin("target kind", test.target.name, host.target_kind(test.target.name));
  for (const auto& h : test.contact_handlers) plugins += ", " + plugin("contact handler", h.name, host.contact_handler(h.name));
  for (const auto& m : test.metrics) plugins += ", " + plugin("metric", m.name, host.metric(m.name));
  note->head = "salsa: test '" + test.name + "' (" + test.source + ") ";
  // One line, whatever the names hold.
  note->tail = " of " + std::to_string(test.steps()) + "; plugins: " + plugins + "; rows so far in " + work.string();
  for (char& c : note->tail)
    if (c == '\n' || c == '\r') c = ' ';
  note->tail += "\n";
  note->step.store(0, std::memory_order_relaxed);
  note->thread.store(::gettid(), std::memory_order_relaxed);
  note->active.store(true, std::memory_order_release);
  return note;
}

// ---- Public

std::string signal_name(int signal) {
  const char* name = signal_text(signal);
  return name ? name : "signal " + std::to_string(signal);
}

void stop_may_exit(bool yes) { may_exit.store(yes); }

int stop_signal() { return stop_requested.load(); }

void install_signal_handlers() {
  if (handlers_installed.exchange(true)) return;
  // Crash notes run on their own stack, so a stack overflow on the main thread is still reported.
  static std::vector<char> alt_stack(std::max<std::size_t>(SIGSTKSZ, 1 << 16));
  stack_t ss{};
  ss.ss_sp = alt_stack.data();
  ss.ss_size = alt_stack.size();
  ::sigaltstack(&ss, nullptr);
  struct sigaction fatal {};
  fatal.sa_handler = on_fatal_signal;
  fatal.sa_flags = SA_ONSTACK | SA_RESETHAND | SA_NODEFER;
  sigemptyset(&fatal.sa_mask);
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::sigaction(sig, &fatal, nullptr);
  struct sigaction stop {};
  stop.sa_handler = on_stop_signal;
  stop.sa_flags = SA_RESTART;
  sigemptyset(&stop.sa_mask);
  ::sem_init(&stop_posted, 0, 0);
  try {
    std::thread(watchdog).detach();
  } catch (const std::system_error&) {  // no thread: a stop waits for the step to end, as before
  }
  for (int sig : {SIGINT, SIGTERM}) ::sigaction(sig, &stop, nullptr);
}

}  // namespace salsa
