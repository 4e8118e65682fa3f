// Running a benchmark's child process (a `gslift run`) so that its peak memory is its own: the
// benches that time whole pipelines share this.
#pragma once

#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <chrono>
#include <string>
#include <vector>

extern char** environ;

namespace gslift::bench {

struct ChildRun {
  bool started = false;
  int status = 0;      // as wait4 reports it
  double wall_s = 0;   // spawn to exit
  double peak_mb = 0;  // the child's own peak RSS (wait4 ru_maxrss)
};

// Runs args[0] with args (no shell) and waits for it.
inline ChildRun run_child_process(std::vector<std::string> args) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  ChildRun r;
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return r;
  r.started = true;
  rusage usage{};
  wait4(pid, &r.status, 0, &usage);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.peak_mb = usage.ru_maxrss / 1024.0;
  return r;
}

}  // namespace gslift::bench
