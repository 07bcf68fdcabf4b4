#pragma once
// Signals in a front-end that runs tests in the foreground (the CLI): stop requests and crash notes.
#include <string>

namespace salsa {

/// For front-ends that run tests in the foreground (the CLI), once, before the first test:
/// - SIGINT / SIGTERM ask the running test to stop (run_test then throws Interrupted); a second one
///   ends the process at once, and so does a watchdog thread when the run has not ended 0.8 s after
///   the first (a step may take minutes) while a test steps (or stop_may_exit allows): it prints each running test's line ("stopped by SIGTERM
///   at step N of M; ... rows so far in ...") and exits with 128 + the signal, the tests' .partial
///   folders left for --resume;
/// - SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT print one line naming the test, the step and the
///   plugins it runs (prepared before the test, written with write(2) only), then end the process
///   with that signal;
/// - a plugin calling exit() or quick_exit() during a test prints the same kind of line and the
///   process ends with status 1.
void install_signal_handlers();

/// Whether the watchdog may end the process when no test is stepping in it (true at first: the
/// front-end's start-up has nothing to lose). A front-end says false once it runs tests: between
/// tests it stops by itself and writes what it owes (a queue's summary), and --isolate's children stop
/// themselves.
void stop_may_exit(bool yes);

/// The signal that asked the run to stop (SIGINT or SIGTERM), or 0.
int stop_signal();

/// "SIGSEGV (segmentation fault)", for messages.
std::string signal_name(int signal);

}  // namespace salsa
