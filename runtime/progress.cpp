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

double step_fraction(const TrainingStep& step) {
  if (step.total <= 0) return 0;
  return std::clamp(static_cast<double>(step.step) / step.total, 0.0, 1.0);
}

double seconds_left(double elapsed_s, int steps_timed, int steps_left) {
  if (steps_timed <= 0 || !(elapsed_s >= 0)) return std::numeric_limits<double>::quiet_NaN();
  return elapsed_s / steps_timed * std::max(0, steps_left);
}

std::string duration_text(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buf[48];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%ld s", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%ld min %02ld s", s / 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return buf;
}

std::string training_step_text(const TrainingStep& step, double left_s) {
  char buf[160];
  std::string text;
  std::snprintf(buf, sizeof buf, "step %d/%d", step.step, step.total);
  text += buf;
  if (!std::isnan(step.loss)) {
    std::snprintf(buf, sizeof buf, "  loss %.4g", step.loss);
    text += buf;
  }
  if (!std::isnan(step.train_psnr)) {
    std::snprintf(buf, sizeof buf, "  train PSNR %.2f dB", step.train_psnr);
    text += buf;
  }
  if (!std::isnan(left_s)) text += "  " + duration_text(left_s) + " left";
  return text;
}

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

bool ConsoleProgress::claim_turn(int64_t now) {
  const int64_t interval_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(interval_).count();
  int64_t last = last_shown_ns_.load(std::memory_order_relaxed);
  if (last != kNever && now - last < interval_ns) return false;
  return last_shown_ns_.compare_exchange_strong(last, now);
}

void ConsoleProgress::node_progress(const std::string& id, double fraction,
                                    const std::string& what) {
  if (!claim_turn(now_ns())) return;
  std::lock_guard<std::mutex> lock(mutex_);
  show_locked(id, fraction, what);
}

void ConsoleProgress::node_step(const std::string& id, const TrainingStep& step) {
  const int64_t now = now_ns();
  FirstStep first{};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    first = first_step_.try_emplace(id, FirstStep{now, step.step}).first->second;
  }
  if (!claim_turn(now)) return;
  const double left = seconds_left(static_cast<double>(now - first.ns) * 1e-9,
                                   step.step - first.step, step.total - step.step);
  std::lock_guard<std::mutex> lock(mutex_);
  show_locked(id, step_fraction(step), training_step_text(step, left));
}

void ConsoleProgress::show_locked(const std::string& id, double fraction, const std::string& what) {
  const int percent = static_cast<int>(std::lround(100.0 * std::clamp(fraction, 0.0, 1.0)));
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
  first_step_.erase(id);
  clear_line_locked();
  if (status == "ok")
    spdlog::info("{} done in {:.2f} s", id, seconds);
  else
    spdlog::warn("{} {} after {:.2f} s", id, status, seconds);
}

}  // namespace gslift
