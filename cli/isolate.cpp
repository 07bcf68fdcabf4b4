#include "isolate.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "embed.hpp"
#include "salsa/core/run/runner.hpp"

namespace salsa::cli {

std::pair<int, std::string> run_isolated(const TestSpec& test, const PluginHost& host, int argc, char** argv,
                                         const std::string& threads) {
  // The program again, or the embedding program's command that is it (embed.hpp).
  const std::vector<std::string>& again = embedding().command;
  std::vector<std::string> args = again.empty() ? std::vector<std::string>{"salsa"} : again;
  args.emplace_back("run");
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) != "--isolate") args.emplace_back(argv[i]);
  args.insert(args.end(), {"--only", test.name});
  if (!threads.empty()) args.insert(args.end(), {"--threads", threads});
  std::vector<char*> cargs;
  for (auto& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
  // Its own process group: Ctrl-C reaches this process only, which passes it on once (a second
  // SIGINT would end the child at once instead of stopping it cleanly).
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, again.empty() ? "/proc/self/exe" : again[0].c_str(), &actions, &attributes, cargs.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(pipe_fds[1]);
  if (spawned != 0) {
    ::close(pipe_fds[0]);
    throw TestFailure("test '" + test.name + "': cannot start its process (" + std::strerror(spawned) + ")");
  }
  std::string said;
  int passed_on = 0;  // the stop signal handed to the child
  char buffer[4096];
  for (;;) {
    if (const int sig = stop_signal(); sig && !passed_on) {
      ::kill(pid, sig);
      passed_on = sig;
    }
    pollfd p{pipe_fds[0], POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    const ssize_t n = ::read(pipe_fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    said.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(pipe_fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // A child that died of the stop signal we handed it (before its own handlers were in place) was
  // interrupted, not crashed: the line that says where the run stopped is ours to print.
  if (WIFSIGNALED(status) && said.find_first_not_of(" \n") == std::string::npos && WTERMSIG(status) != passed_on)
    said = "salsa: test '" + test.name + "' (" + test.source + ") died of " + signal_name(WTERMSIG(status)) +
           " in its own process (--isolate); behavior '" + test.groups[0].behavior.name + "' (" +
           host.behavior(test.groups[0].behavior.name).plugin().file.string() + ")\n";
  else if (WIFSIGNALED(status) && WTERMSIG(status) == passed_on && said.find_first_not_of(" \n") == std::string::npos)
    said = "salsa: " + signal_name(passed_on) + ": stopped test '" + test.name + "' (" + test.source +
           ") before it began (run again with --resume to redo it)\n";
  return {status, said};
}


}  // namespace salsa::cli
