// Running a child process (a `gslift run`) so that its crashes are its own: `gslift sweep`,
// `gslift batch` and the benches that time whole pipelines share this.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>
#include <vector>

namespace gslift {

struct ChildRun {
  bool started = false;
  int status = 0;     // as wait4 reports it
  double wall_s = 0;  // spawn to exit
  // wait4's ru_maxrss. Not the child's own peak when the parent is large: exec carries the
  // replaced address space's peak into it (a forked child's starts at the parent's resident
  // size). A `gslift run` child records its own (VmHWM) in run.json: read that where the parent
  // may be large (sweep, batch).
  double peak_mb = 0;
};

// "killed by signal 11 (Segmentation fault)", "exit code 3", "could not start".
inline std::string child_exit_text(const ChildRun& r) {
  if (!r.started) return "could not start";
  if (WIFSIGNALED(r.status))
    return "killed by signal " + std::to_string(WTERMSIG(r.status)) + " (" +
           strsignal(WTERMSIG(r.status)) + ")";
  return "exit code " + std::to_string(WEXITSTATUS(r.status));
}

// Runs args[0] with args (no shell) and waits for it. With `log`, the child's stdout and stderr
// go to that file (created or truncated) instead of the parent's.
//
// The child dies with the thread that started it (PR_SET_PDEATHSIG): a batch or sweep killed
// with -9 leaves no child writing into a folder that the next run removes and reuses. It runs in
// a process group of its own, so that a terminal's Ctrl-C reaches the parent alone; when `cancel`
// becomes true while the parent waits (its SIGINT/SIGTERM handler, runtime/signals.hpp), the
// child gets one SIGTERM and stops as a `gslift run` does.
inline ChildRun run_child_process(std::vector<std::string> args, const std::string& log = {},
                                  const std::atomic<bool>* cancel = nullptr) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  ChildRun r;
  if (::access(argv[0], X_OK) != 0) return r;
  int log_fd = -1;
  if (!log.empty()) {
    log_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (log_fd < 0) return r;
  }
  const pid_t parent = ::getpid();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {  // only async-signal-safe calls until exec
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
    ::setpgid(0, 0);
    if (log_fd >= 0) {
      ::dup2(log_fd, 1);
      ::dup2(log_fd, 2);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  if (log_fd >= 0) ::close(log_fd);
  if (pid < 0) return r;
  r.started = true;
  rusage usage{};
  bool forwarded = false;
  // The parent's signal handlers interrupt the wait (they are installed without SA_RESTART).
  while (true) {
    if (cancel && cancel->load() && !forwarded) {
      ::kill(pid, SIGTERM);
      forwarded = true;
    }
    if (::wait4(pid, &r.status, 0, &usage) >= 0 || errno != EINTR) break;
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.peak_mb = usage.ru_maxrss / 1024.0;
  return r;
}

}  // namespace gslift
