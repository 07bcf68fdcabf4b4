// Linked into every suite. At exit, before LeakSanitizer's check (it runs last, from the sanitizer
// runtime's own destructor), wait up to 2 s for the threads a library named and is ending to be gone.
// QtTest's watchdog thread is detached: its QThread is destroyed when the tests end, but the thread can
// still be in its exit path, where LeakSanitizer scans neither its stack nor its thread-local storage, so
// the Qt thread data it is about to free (152 B) was reported as a leak on a loaded machine.
// Threads that keep the process's name (oneTBB's workers) stay for the life of the process: not awaited.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <unistd.h>

namespace {

std::string thread_name(const std::filesystem::path& task) {
  std::ifstream in(task / "comm");
  std::string name;
  std::getline(in, name);
  return name;
}

bool named_threads_left() {
  const std::string process_name = thread_name("/proc/self");
  const std::string me = std::to_string(gettid());
  std::error_code error;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", error)) {
    if (task.path().filename() == me) continue;
    const std::string name = thread_name(task.path());
    if (!name.empty() && name != process_name) return true;  // empty: it ended while we looked
  }
  return false;
}

struct AwaitExitingThreads {
  ~AwaitExitingThreads() {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (named_threads_left() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
} await_exiting_threads;

}  // namespace
