// Where the executor reports what nodes are doing: start, fractional progress of long nodes, end.
// The CLI shows it as one updating line on a terminal and as throttled log lines otherwise (a
// batch job's log must not fill with carriage returns); tests can plug in their own sink.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <string>

#include "base/training_step.hpp"

namespace gslift {

// step / total clamped to [0, 1] (0 when total is not positive).
double step_fraction(const TrainingStep& step);

// The seconds a loop has left at its pace so far: the seconds `steps_timed` steps took, per step,
// times the steps left; NaN before a step was timed.
double seconds_left(double elapsed_s, int steps_timed, int steps_left);

// "42 s", "3 min 05 s", "1 h 02 min".
std::string duration_text(double seconds);

// The step's fields as one line: "step 120/500  loss 0.04213  train PSNR 24.31 dB", and
// "  38 s left" when `left_s` is a number (a NaN loss or PSNR is left out).
std::string training_step_text(const TrainingStep& step,
                               double left_s = std::numeric_limits<double>::quiet_NaN());

class ProgressSink {
 public:
  virtual ~ProgressSink() = default;
  // All three may be called concurrently from different nodes' threads.
  virtual void node_started(const std::string& id, const std::string& type) = 0;
  // fraction in [0,1]; `what` is a short free-form phase ("iteration 120/500").
  virtual void node_progress(const std::string& id, double fraction, const std::string& what) = 0;
  // A training loop's step; a sink that keeps no clock shows it as node_progress with its text.
  virtual void node_step(const std::string& id, const TrainingStep& step) {
    node_progress(id, step_fraction(step), training_step_text(step));
  }
  // status is the NodeStatus name ("ok", "failed", "cancelled"); seconds is the node's wall time.
  virtual void node_finished(const std::string& id, const std::string& status, double seconds) = 0;
};

// The CLI's sink. On a terminal (`tty`) it redraws a single line on `stream` at most every
// `tty_interval`; otherwise it logs (spdlog, info) at most once per `log_interval` per run, so a
// node that reports progress every iteration costs one clock read per call. A training step's
// line adds the time left, at the pace since the node's first step (its setup, decoding the
// views, is not a step's cost).
class ConsoleProgress : public ProgressSink {
 public:
  ConsoleProgress(bool tty, std::FILE* stream,
                  std::chrono::milliseconds tty_interval = std::chrono::milliseconds(100),
                  std::chrono::milliseconds log_interval = std::chrono::seconds(5));
  ~ConsoleProgress() override;

  void node_started(const std::string& id, const std::string& type) override;
  void node_progress(const std::string& id, double fraction, const std::string& what) override;
  void node_step(const std::string& id, const TrainingStep& step) override;
  void node_finished(const std::string& id, const std::string& status, double seconds) override;

 private:
  // Erases the progress line so that a log line does not land in the middle of it.
  void clear_line_locked();
  // Whether a call at `now` (steady clock ns) may show a line: one caller per interval wins, the
  // others return at once.
  bool claim_turn(int64_t now);
  void show_locked(const std::string& id, double fraction, const std::string& what);

  bool tty_;
  std::FILE* stream_;
  std::chrono::steady_clock::duration interval_;
  std::mutex mutex_;
  // Nanoseconds (steady clock) of the last line drawn or logged, kNever before the first one (so
  // that the first report always shows, even within `interval` of the clock's epoch, i.e. of the
  // machine's boot); checked without the lock.
  static constexpr int64_t kNever = INT64_MIN;
  std::atomic<int64_t> last_shown_ns_{kNever};
  bool line_shown_ = false;
  struct FirstStep {
    int64_t ns;
    int step;
  };
  std::map<std::string, FirstStep> first_step_;  // each running node's first reported step
};

// True when `stream` is an interactive terminal.
bool is_terminal(std::FILE* stream);

}  // namespace gslift
