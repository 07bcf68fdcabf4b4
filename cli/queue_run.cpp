#include "queue_run.hpp"

#include <sys/ioctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "salsa/plots/results.hpp"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

namespace salsa::cli {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

/// How a test ended, reported by its worker thread to the main thread.
struct Event {
  enum Kind { ok, skipped, failed, interrupted, write_error } kind = ok;
  std::size_t slot = 0;
  std::string message;  // one line: why it failed or where it stopped
  std::string plots_failed;  // why its plots could not be drawn (the test itself is fine)
  double wall_seconds = 0;
};

/// A worker: one thread running one test at a time.
struct Slot {
  std::thread thread;
  std::size_t index = 0;
  bool busy = false;
  std::atomic<std::size_t> steps{0};  // the running test's steps so far
};

double read_wall_seconds(const fs::path& folder) {
  std::ifstream in(folder / "timing.json");
  try {
    return nlohmann::json::parse(in).value("wall_seconds", 0.0);
  } catch (const std::exception&) {
    return 0;
  }
}

/// Targets and targets found, counted in targets.csv (found_time is the 4th column).
std::pair<std::size_t, std::size_t> targets_in(const fs::path& folder) {
  std::ifstream in(folder / "targets.csv");
  std::string line;
  std::size_t targets = 0, found = 0;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    ++targets;
    std::size_t field = 0, start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i)
      if (i == line.size() || line[i] == ',') {
        if (field++ == 3 && i > start) ++found;
        start = i + 1;
      }
  }
  return {targets, found};
}

/// The last non-empty line of `text`, or "".
std::string last_line(const std::string& text) {
  std::istringstream lines(text);
  std::string line, last;
  while (std::getline(lines, line))
    if (!line.empty()) last = line;
  if (last.starts_with("salsa: ")) last = last.substr(7);
  return last;
}

std::string duration_text(double seconds) {
  if (!(seconds < 1e9)) return "?";
  const auto s = static_cast<long long>(seconds + 0.5);
  char text[32];
  if (s >= 3600) std::snprintf(text, sizeof text, "%lldh%02lldm", s / 3600, s / 60 % 60);
  else if (s >= 60) std::snprintf(text, sizeof text, "%lldm%02llds", s / 60, s % 60);
  else std::snprintf(text, sizeof text, "%llds", s);
  return text;
}

/// The live bar (a terminal) or one line per finished test (anything else); nothing under --quiet.
class Progress {
 public:
  Progress(const QueueRunOptions& o, std::size_t total, std::size_t queue_size)
      : options_(o), total_(total), queue_size_(queue_size), start_(Clock::now()) {}

  /// A finished test: "[<its place in the queue>/<queue size>] <line>".
  void test_done(std::size_t index, const std::string& line) {
    if (options_.quiet) return;
    if (options_.terminal) return redraw_soon();
    std::cout << "[" << index + 1 << "/" << queue_size_ << "] " << line << std::endl;
  }
  /// Before a line on stderr: the bar's line is cleared first, so the two do not mix.
  void before_error() {
    if (shown_) std::cout << "\r\033[K" << std::flush, shown_ = false;
  }
  void redraw_soon() { last_draw_ = {}; }
  void draw(std::size_t done, std::size_t failed, std::size_t running, double simulated, double remaining) {
    if (options_.quiet || !options_.terminal) return;
    const auto now = Clock::now();
    if (now - last_draw_ < std::chrono::milliseconds(250)) return;
    last_draw_ = now;
    const double wall = std::chrono::duration<double>(now - start_).count();
    const double rate = wall > 0 ? simulated / wall : 0;
    std::ostringstream s;
    s << options_.label;
    const std::size_t width = 20, filled = total_ ? width * (done + failed) / total_ : width;
    s << "[" << std::string(filled, '#') << std::string(width - filled, '-') << "] " << done + failed << "/" << total_ << " tests";
    if (failed) s << ", " << failed << " failed";
    s << ", " << running << " running, ";
    s.precision(3);
    s << rate << " sim s/s, ETA " << (rate > 0 ? duration_text(remaining / rate) : "?");
    std::string text = s.str();
    winsize ws{};
    if (::ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 1 && text.size() >= ws.ws_col) text.resize(ws.ws_col - 1);
    std::cout << "\r\033[K" << text << std::flush;
    shown_ = true;
  }
  void end() {
    if (shown_) std::cout << "\n" << std::flush, shown_ = false;
  }

 private:
  const QueueRunOptions& options_;
  std::size_t total_, queue_size_;
  Clock::time_point start_, last_draw_{};
  bool shown_ = false;
};

}  // namespace

std::string finished_line(const TestSpec& test, const fs::path& folder, double wall_seconds) {
  const auto [targets, found] = targets_in(folder);
  char text[160];
  std::snprintf(text, sizeof text, "%.2f s simulated in %.2f s, %zu/%zu targets found -> ", test.time, wall_seconds, found, targets);
  return text + folder.string();
}

QueueResult run_queue(const std::vector<TestSpec>& tests, const PluginHost& host, const RunOptions& options,
              const QueueRunOptions& run, Dispatch& dispatch) {
  std::vector<std::unique_ptr<Slot>> slots;
  for (std::size_t i = 0; i < std::max<std::size_t>(run.jobs, 1); ++i) slots.push_back(std::make_unique<Slot>());
  std::mutex mutex;  // guards events
  std::condition_variable wake;
  std::deque<Event> events;

  // ---- A worker runs its test and reports how it ended; all printing is the main thread's.
  auto work = [&](Slot& slot) {
    const TestSpec& test = tests[slot.index];
    Event e;
    for (std::size_t i = 0; i < slots.size(); ++i)
      if (slots[i].get() == &slot) e.slot = i;
    try {
      if (run.isolated && !already_done(test, host, options)) {
        const auto [status, said] = run.isolated(test);
        const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        e.message = last_line(said);
        if (status == 0) {
          e.wall_seconds = read_wall_seconds(options.out / test.name);
        } else if (stop_signal() && (code == 130 || code == 143 || (WIFSIGNALED(status) && WTERMSIG(status) == stop_signal()))) {
          e.kind = Event::interrupted;
        } else {
          e.kind = code == 1 && (e.message.find("write failed") != std::string::npos || e.message.find("cannot create file") != std::string::npos) ? Event::write_error : Event::failed;
          if (WIFSIGNALED(status)) record_failure(options.out, test.name, e.message);  // the child could not
        }
      } else {
        RunOptions mine = options;
        mine.progress = &slot.steps;
        const RunResult r = run_test(test, host, mine);
        e.kind = r.skipped ? Event::skipped : Event::ok;
        e.wall_seconds = r.wall_seconds;
      }
    } catch (const TestFailure& x) {
      e.kind = Event::failed, e.message = x.what();
    } catch (const Interrupted& x) {
      e.kind = Event::interrupted, e.message = x.what();
    } catch (const WriteError& x) {
      e.kind = Event::write_error, e.message = x.what();
    } catch (const std::exception& x) {  // InputError (a folder taken since the check), or worse
      e.kind = Event::failed, e.message = x.what();
    }
    // Its plots, drawn here so that they keep pace with the tests (QPainter on QImage: any thread); a
    // finished test whose plots were cut off (killed while drawing) gets them now.
    const bool draw = e.kind == Event::ok || (e.kind == Event::skipped && plots::test_plots_missing(options.out / test.name));
    if (draw && run.plots) try {
        plots::draw_test_plots(options.out / test.name);
      } catch (const std::exception& x) {
        e.plots_failed = x.what();
      }
    {
      std::lock_guard lock(mutex);
      events.push_back(std::move(e));
    }
    wake.notify_one();
  };

  // ---- The main thread: starts tests in queue order, handles what ended, draws progress.
  if (run.plots) plots::start_plotting();
  Progress progress(run, run.expected, tests.size());
  std::size_t running = 0, done = 0, failed = 0;
  double simulated = 0, remaining = 0;  // s simulated here so far; s left of the tests handed out
  bool exhausted = false, write_failed = false;
  std::vector<std::pair<std::size_t, std::string>> stopped;  // (queue index, where it stopped)
  std::optional<std::size_t> next_up;  // handed out but not started (stop asked meanwhile)
  for (;;) {
    // Start tests while a slot is free, unless a stop was asked or a write failed.
    while (!exhausted && !stop_signal() && !write_failed) {
      auto free = std::find_if(slots.begin(), slots.end(), [](const auto& s) { return !s->busy; });
      if (free == slots.end()) break;
      next_up = dispatch.next();
      if (!next_up) {
        exhausted = true;
        break;
      }
      Slot& slot = **free;
      slot.index = *next_up;
      next_up.reset();
      slot.busy = true;
      slot.steps.store(0);
      ++running;
      slot.thread = std::thread(work, std::ref(slot));
    }
    // Progress: finished tests plus the running ones' steps.
    double now = simulated, left = 0;
    for (const auto& s : slots)
      if (s->busy) {
        const TestSpec& t = tests[s->index];
        const double in = static_cast<double>(s->steps.load(std::memory_order_relaxed)) * t.dt;
        now += in, left += t.time - in;
      }
    remaining = left;
    if (run.expected > done + failed + running) {  // the tests not started, estimated from the mean so far
      const std::size_t started = done + failed + running;
      double mean = 0;
      for (const auto& s : slots)
        if (s->busy) mean += tests[s->index].time;
      mean = started ? (simulated + mean) / static_cast<double>(started) : tests.empty() ? 0 : tests.front().time;
      remaining += mean * static_cast<double>(run.expected - started);
    }
    progress.draw(done, failed, running, now, remaining);
    dispatch.serve();
    if (running == 0 && (exhausted || stop_signal() || write_failed) && dispatch.all_done()) break;
    std::deque<Event> ended;
    {
      std::unique_lock lock(mutex);
      wake.wait_for(lock, std::chrono::milliseconds(50), [&] { return !events.empty(); });
      ended.swap(events);
    }
    for (Event& e : ended) {
      Slot& slot = *slots[e.slot];
      slot.thread.join();
      slot.busy = false;
      --running;
      const TestSpec& test = tests[slot.index];
      const fs::path folder = options.out / test.name;
      switch (e.kind) {
        case Event::ok:
          ++done;
          simulated += test.time;
          progress.test_done(slot.index, test.name + ": " + finished_line(test, folder, e.wall_seconds));
          if (!e.plots_failed.empty()) {
            progress.before_error();
            std::cerr << "salsa: warning: plots of test '" << test.name << "': " << e.plots_failed << std::endl;
          }
          break;
        case Event::skipped:
          ++done;
          progress.test_done(slot.index, test.name + ": already complete, skipped");
          break;
        case Event::write_error:
          write_failed = true;
          [[fallthrough]];
        case Event::failed:
          ++failed;
          progress.before_error();
          std::cerr << "salsa: " << e.message << std::endl;
          break;
        case Event::interrupted:
          stopped.emplace_back(slot.index, e.message);
          break;
      }
    }
  }
  progress.end();
  dispatch.finished(failed);

  if (const int sig = stop_signal(); !stopped.empty() || (sig && (!exhausted || next_up))) {
    std::sort(stopped.begin(), stopped.end());
    if (stopped.size() == 1) {
      std::cerr << "salsa: " << stopped.front().second << std::endl;
    } else if (!stopped.empty()) {
      // One line for all of them: "SIGINT: stopped test 'a' (...) at t = 3 s; test 'b' ... (run again ...)".
      std::string line = signal_name(sig) + ": stopped " + std::to_string(stopped.size()) + " tests: ";
      for (std::size_t i = 0; i < stopped.size(); ++i) {
        std::string part = stopped[i].second;
        if (const auto colon = part.find(": stopped "); colon != std::string::npos) part = part.substr(colon + 10);
        if (const auto tail = part.find(" (run again"); tail != std::string::npos) part = part.substr(0, tail);
        line += (i ? " | " : "") + part;
      }
      std::cerr << "salsa: " << line << " (run again with --resume to redo them)" << std::endl;
    } else {
      std::cerr << "salsa: " << signal_name(sig) << ": stopped before the next test (run again with --resume for the rest)" << std::endl;
    }
    return {128 + (sig ? sig : SIGINT), write_failed};
  }
  return {failed ? 1 : 0, write_failed};
}

}  // namespace salsa::cli
