#include <cstdio>
#include <string>

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
