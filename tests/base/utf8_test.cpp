// base/utf8.hpp: what a message may print of its input (issue 33: a 200 MB header line became
// 200 MB of stderr; terminal escape sequences in a capture.yaml value reached the terminal raw).
#include "base/utf8.hpp"

#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("escape_invalid_utf8 escapes ill-formed bytes and NUL, nothing else", "[utf8]") {
  CHECK(escape_invalid_utf8("caf\xc3\xa9") == "caf\xc3\xa9");
  CHECK(escape_invalid_utf8(std::string("a\xff\0b\n", 5)) == "a\\xFF\\x00b\n");
  CHECK(escape_invalid_utf8("\xed\xa0\x80") == "\\xED\\xA0\\x80");  // a surrogate
  CHECK(escape_invalid_utf8("\x1b[31m") == "\x1b[31m");  // JSON escapes control characters itself
}

TEST_CASE("printable escapes control characters and caps the excerpt", "[utf8]") {
  CHECK(printable("cam_01 \xe2\x86\x92 ok") == "cam_01 \xe2\x86\x92 ok");
  CHECK(printable("\x1b[2Jred\tx\ny\x7f") == "\\x1B[2Jred\\x09x\\x0Ay\\x7F");
  CHECK(printable("a\xc2\x9b"
                  "31m") == "a\\xC2\\x9B31m");  // C1 CSI, which terminals obey
  CHECK(printable("\xc3\xa9\xff") == "\xc3\xa9\\xFF");
  const std::string header(2000000, 'x');
  const std::string p = printable(header);
  CHECK(p == std::string(kMaxQuotedBytes, 'x') + "... (2000000 bytes)");
  // The cut falls between characters, never inside one.
  CHECK(printable("ab\xc3\xa9z", 3) == "ab\xc3\xa9... (5 bytes)");
  CHECK(printable("abc", 3) == "abc");
}

TEST_CASE("terminal_safe escapes what a terminal obeys and keeps the message's lines", "[utf8]") {
  CHECK(terminal_safe("error: a\n  hint\tb") == "error: a\n  hint\tb");
  CHECK(terminal_safe("value \x1b]0;title\x07 \x1b[2J") == "value \\x1B]0;title\\x07 \\x1B[2J");
  CHECK(terminal_safe("a\xc2\x9b"
                      "1m") == "a\\xC2\\x9B1m");  // C1 CSI as UTF-8
  // Raw bytes: 0x9B is CSI to an 8-bit terminal; Latin-1 letters print as they are.
  CHECK(terminal_safe("caf\xe9 \x9b"
                      "2J") == "caf\xe9 \\x9B2J");
  CHECK(terminal_safe(std::string("a\0b", 3)) == "a\\x00b");
}
