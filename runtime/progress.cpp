#include "runtime/progress.hpp"

#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>
#include <unistd.h>

namespace gslift {

namespace {
int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

bool is_terminal(std::FILE* stream) {
  return ::isatty(::fileno(stream)) == 1;
}

ConsoleProgress::ConsoleProgress(bool tty, std::FILE* stream,
                                 std::chrono::milliseconds tty_interval,
                                 std::chrono::milliseconds log_interval)
    : tty_(tty), stream_(stream), interval_(tty ? tty_interval : log_interval) {}

ConsoleProgress::~ConsoleProgress() {
  std::lock_guard<std::mutex> lock(mutex_);
  clear_line_locked();
}

void ConsoleProgress::clear_line_locked() {
  if (!line_shown_) return;
  std::fputs("\r\033[K", stream_);
  std::fflush(stream_);
  line_shown_ = false;
}

void ConsoleProgress::node_started(const std::string& id, const std::string& type) {
  std::lock_guard<std::mutex> lock(mutex_);
  clear_line_locked();
  spdlog::info("{} ({}) started", id, type);
}

void ConsoleProgress::node_progress(const std::string& id, double fraction,
                                    const std::string& what) {
  const int64_t now = now_ns();
  const int64_t interval_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(interval_).count();
  int64_t last = last_shown_ns_.load(std::memory_order_relaxed);
  if (last != kNever && now - last < interval_ns) return;
  // One caller per interval wins the right to print; the others return at once.
  if (!last_shown_ns_.compare_exchange_strong(last, now)) return;
  const int percent = static_cast<int>(std::lround(100.0 * std::clamp(fraction, 0.0, 1.0)));
  std::lock_guard<std::mutex> lock(mutex_);
  if (tty_) {
    std::fprintf(stream_, "\r\033[K%s %3d%% %s", id.c_str(), percent, what.c_str());
    std::fflush(stream_);
    line_shown_ = true;
  } else {
    spdlog::info("{} {}% {}", id, percent, what);
  }
}

void ConsoleProgress::node_finished(const std::string& id, const std::string& status,
                                    double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  clear_line_locked();
  if (status == "ok")
    spdlog::info("{} done in {:.2f} s", id, seconds);
  else
    spdlog::warn("{} {} after {:.2f} s", id, status, seconds);
}

}  // namespace gslift
