// runtime/log_format.hpp: a log line carries capture values (issue 33: a folder name with an escape
// sequence, a megabyte-long reply error); the formatter escapes and caps every message.
#include <sstream>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "runtime/log_format.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("log lines escape control characters and cap the message", "[log]") {
  std::ostringstream out;
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(out);
  spdlog::logger logger("log_format_test", sink);
  logger.set_formatter(log_formatter());
  logger.warn("capture {} failed: {}", "cam\x1b]0;x\x07", std::string(1000000, 'e'));
  const std::string line = out.str();
  CHECK(line.find("[warning] capture cam\\x1B]0;x\\x07 failed: eee") != std::string::npos);
  CHECK(line.find_first_of("\x1b\x07") == std::string::npos);
  CHECK(line.size() < kMaxLogMessageBytes + 100);
  CHECK(line.find("... (1000026 bytes)\n") != std::string::npos);
  out.str("");
  logger.info("two lines\n\tkept");
  CHECK(out.str().find("] [info] two lines\n\tkept\n") != std::string::npos);
}
