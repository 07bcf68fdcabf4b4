#pragma once
// Inside libsalsa: the stop flag the signal handlers set and the crash note each running test keeps
// (core/src/run/signals.cpp), which run_test prepares and updates.
#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {

/// The signal that asked the run to stop (SIGINT or SIGTERM), or 0; set by the handler.
extern std::atomic<int> stop_requested;

// One note per test running in this process (tests may run side by side, --jobs): a slot is taken by
// the thread that runs the test, and the handlers find the faulting thread's slot by its thread id.
struct RunningNote {
  std::string head;  // "salsa: test 'x' (x.json) "
  std::string tail;  // " of 600; plugins: behavior 'b' (file), ...\n"
  std::atomic<bool> taken{false};   // owned by a running test
  std::atomic<bool> active{false};  // head and tail are ready
  std::atomic<pid_t> thread{0};     // the thread stepping the test
  std::atomic<std::uint64_t> step{0};
};
constexpr std::size_t max_notes = 1024;  // the most tests that run at once (--jobs at most 1024)

/// Takes a note slot for `test` and prepares it (on the stepping thread, before the test's plugins
/// run); nullptr without signal handlers. Released by NoteGuard.
RunningNote* prepare_note(const TestSpec& test, const PluginHost& host, const std::filesystem::path& work);

struct NoteGuard {
  RunningNote* note = nullptr;
  ~NoteGuard() {
    if (!note) return;
    note->active.store(false, std::memory_order_release);
    note->taken.store(false, std::memory_order_release);
  }
};

}  // namespace salsa
