// The format of gslift's log lines. A log line carries capture values (a folder name, a VLM
// reply's error, a sweep child's error), which may hold terminal escape sequences or be megabytes
// long; the formatter escapes and caps every message, so no call site has to remember to.
#pragma once

#include <memory>

#include <spdlog/formatter.h>

namespace gslift {

// How much of one log message is printed.
constexpr size_t kMaxLogMessageBytes = 4096;

// "[HH:MM:SS.mmm] [level] message", the message through terminal_safe capped at
// kMaxLogMessageBytes.
std::unique_ptr<spdlog::formatter> log_formatter();

}  // namespace gslift
