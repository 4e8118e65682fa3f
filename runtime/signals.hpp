// SIGINT/SIGTERM handling for the command line: the first signal only sets a flag, which the
// executor turns into a clean cancellation (nodes poll ctx.cancelled(), run.json is still
// written, exit code 130); a second signal exits at once for a user who does not want to wait.
#pragma once

#include <atomic>

namespace gslift {

// The process-wide interruption flag set by the handlers (lock-free, so safe to set in a handler).
std::atomic<bool>& interrupt_flag();

// Installs the handlers for SIGINT and SIGTERM. Idempotent.
void install_interrupt_handlers();

}  // namespace gslift
