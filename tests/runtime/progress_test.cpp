#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "runtime/progress.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {
std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string out;
  for (int c; (c = std::fgetc(f)) != EOF;) out += static_cast<char>(c);
  return out;
}
}  // namespace

TEST_CASE("on a terminal progress redraws one line, throttled, and clears it", "[progress]") {
  std::FILE* f = std::tmpfile();
  REQUIRE(f);
  {
    // An hour: the second call is within the interval on any machine, however loaded.
    ConsoleProgress p(true, f, std::chrono::hours(1));
    p.node_progress("recon", 0.423, "optimising");
    // Within the interval: dropped.
    p.node_progress("recon", 0.5, "optimising");
    CHECK(contents(f) == "\r\033[Krecon  42% optimising");
    std::fseek(f, 0, SEEK_END);
  }
  // The destructor erases the line it left.
  CHECK(contents(f) == "\r\033[Krecon  42% optimising\r\033[K");
  std::fclose(f);
}

TEST_CASE("progress fractions are clamped to 0..100%", "[progress]") {
  std::FILE* f = std::tmpfile();
  REQUIRE(f);
  {
    // Scoped: the destructor erases the line, so it must run before the file is closed.
    ConsoleProgress p(true, f, std::chrono::milliseconds(0));
    p.node_progress("a", 1.7, "x");
    p.node_progress("a", -0.2, "y");
    CHECK(contents(f) == "\r\033[Ka 100% x\r\033[Ka   0% y");
  }
  std::fclose(f);
}

TEST_CASE("a training step's line has step / total, loss, train PSNR and the time left",
          "[progress]") {
  const TrainingStep step{120, 500, 0.0421337, 24.3149};
  // 30 s for the 120 steps timed: 0.25 s a step, 380 steps left: 95 s.
  CHECK(seconds_left(30.0, 120, 380) == Approx(95.0));
  CHECK(training_step_text(step, seconds_left(30.0, 120, 380)) ==
        "step 120/500  loss 0.04213  train PSNR 24.31 dB  1 min 35 s left");
  // No step timed yet: no time left; a loop that renders nothing has no PSNR.
  CHECK(training_step_text({7, 300, 1.5}) == "step 7/300  loss 1.5");
  CHECK(std::isnan(seconds_left(4.0, 0, 300)));
  CHECK(duration_text(42.4) == "42 s");
  CHECK(duration_text(3725) == "1 h 02 min");
  CHECK(step_fraction({120, 500}) == Approx(0.24));
  CHECK(step_fraction({3, 0}) == 0);
}

TEST_CASE("a training step on a terminal and in a log shows the same fields", "[progress]") {
  std::FILE* f = std::tmpfile();
  REQUIRE(f);
  {
    ConsoleProgress p(true, f, std::chrono::milliseconds(0));
    p.node_started("recon", "splat.reconstruct");
    // The first step has no pace yet; the second has (its value depends on the clock).
    p.node_step("recon", {1, 500, 0.47, 14.97});
    CHECK(contents(f) == "\r\033[Krecon   0% step 1/500  loss 0.47  train PSNR 14.97 dB");
    std::fseek(f, 0, SEEK_END);
    p.node_step("recon", {250, 500, 0.03, 21.5});
    const std::string line = contents(f);
    CHECK(line.find("\r\033[Krecon  50% step 250/500  loss 0.03  train PSNR 21.50 dB  ") !=
          std::string::npos);
    CHECK(line.substr(line.size() - 5) == " left");
    std::fseek(f, 0, SEEK_END);
  }
  std::fclose(f);
}

namespace {

// A sink that keeps what it was told (ProgressSink's default node_step).
struct StepTextSink : ProgressSink {
  std::vector<std::string> lines;
  void node_started(const std::string&, const std::string&) override {}
  void node_progress(const std::string& id, double fraction, const std::string& what) override {
    lines.push_back(id + " " + std::to_string(static_cast<int>(100 * fraction)) + " " + what);
  }
  void node_finished(const std::string&, const std::string&, double) override {}
};

}  // namespace

TEST_CASE("a sink without a clock gets a training step as its fraction and fields", "[progress]") {
  StepTextSink sink;
  ProgressSink& base = sink;
  base.node_step("instfeat", {30, 300, 0.5});
  REQUIRE(sink.lines.size() == 1);
  CHECK(sink.lines[0] == "instfeat 10 step 30/300  loss 0.5");
}
