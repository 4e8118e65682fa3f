#include "runtime/signals.hpp"

#include <csignal>

#include <unistd.h>

#include "runtime/exit_codes.hpp"

namespace gslift {

namespace {
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the flag is set from a signal handler");

extern "C" void on_interrupt(int) {
  // Second signal: the user insists; only async-signal-safe calls here.
  if (g_interrupted.exchange(true)) ::_exit(exit_code::kInterrupted);
}
}  // namespace

std::atomic<bool>& interrupt_flag() {
  return g_interrupted;
}

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace gslift
