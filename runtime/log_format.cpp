#include "runtime/log_format.hpp"

#include <spdlog/pattern_formatter.h>

#include "base/utf8.hpp"

namespace gslift {
namespace {

// %* in the pattern: the message, escaped and capped.
class SafeMessage : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&,
              spdlog::memory_buf_t& dest) override {
    const std::string text = terminal_safe(std::string_view(msg.payload.data(), msg.payload.size()),
                                           kMaxLogMessageBytes);
    dest.append(text.data(), text.data() + text.size());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override {
    return std::make_unique<SafeMessage>();
  }
};

}  // namespace

std::unique_ptr<spdlog::formatter> log_formatter() {
  auto formatter = std::make_unique<spdlog::pattern_formatter>();
  formatter->add_flag<SafeMessage>('*').set_pattern("[%H:%M:%S.%e] [%^%l%$] %*");
  return formatter;
}

}  // namespace gslift
