#pragma once
// Signals in a front-end that runs tests in the foreground (the CLI): stop requests and crash notes.
#include <string>

namespace salsa {

/// For front-ends that run tests in the foreground (the CLI), once, before the first test:
/// - SIGINT / SIGTERM ask the running test to stop (run_test then throws Interrupted); a second one
///   ends the process at once;
/// - SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT print one line naming the test, the step and the
///   plugins it runs (prepared before the test, written with write(2) only), then end the process
///   with that signal;
/// - a plugin calling exit() or quick_exit() during a test prints the same kind of line and the
///   process ends with status 1.
void install_signal_handlers();

/// The signal that asked the run to stop (SIGINT or SIGTERM), or 0.
int stop_signal();

/// "SIGSEGV (segmentation fault)", for messages.
std::string signal_name(int signal);

}  // namespace salsa
