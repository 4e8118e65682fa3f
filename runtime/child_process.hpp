// Running a child process (a `gslift run`) so that its peak memory and its crashes are its own:
// `gslift sweep` and the benches that time whole pipelines share this.
#pragma once

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <cerrno>
#include <chrono>
#include <string>
#include <vector>

extern char** environ;

namespace gslift {

struct ChildRun {
  bool started = false;
  int status = 0;      // as wait4 reports it
  double wall_s = 0;   // spawn to exit
  double peak_mb = 0;  // the child's own peak RSS (wait4 ru_maxrss)
};

// Runs args[0] with args (no shell) and waits for it. With `log`, the child's stdout and stderr
// go to that file (created or truncated) instead of the parent's.
inline ChildRun run_child_process(std::vector<std::string> args, const std::string& log = {}) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  ChildRun r;
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!log.empty()) {
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
  }
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return r;
  r.started = true;
  rusage usage{};
  // A signal handler of the parent (SIGINT: the child gets it too) may interrupt the wait.
  while (wait4(pid, &r.status, 0, &usage) < 0 && errno == EINTR) {
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.peak_mb = usage.ru_maxrss / 1024.0;
  return r;
}

}  // namespace gslift
