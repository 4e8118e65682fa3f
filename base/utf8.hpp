// Paths and messages are bytes: a folder with a Latin-1 name, a graph param with a stray byte or
// an error message quoting a binary file are not UTF-8, while JSON strings must be. Standard
// library only, like everything in base/.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gslift {

namespace utf8_detail {

// The length of the well-formed UTF-8 sequence (RFC 3629: no overlong forms, no surrogates,
// nothing above U+10FFFF) that starts at s[i], or 0 if none does. NUL counts as ill-formed: it
// cuts every C string built from the text short.
inline size_t sequence_length(std::string_view s, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<uint8_t>(s[k]); };
  const uint8_t b = byte(i);
  size_t len = 0;
  uint8_t lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
  if (b >= 0x01 && b <= 0x7F)
    len = 1;
  else if (b >= 0xC2 && b <= 0xDF)
    len = 2;
  else if (b >= 0xE0 && b <= 0xEF) {
    len = 3;
    if (b == 0xE0) lo = 0xA0;  // overlong
    if (b == 0xED) hi = 0x9F;  // surrogates
  } else if (b >= 0xF0 && b <= 0xF4) {
    len = 4;
    if (b == 0xF0) lo = 0x90;  // overlong
    if (b == 0xF4) hi = 0x8F;  // above U+10FFFF
  }
  if (len == 0 || i + len > s.size()) return 0;
  for (size_t k = 1; k < len; ++k) {
    const uint8_t c = byte(i + k);
    if (k == 1 ? c < lo || c > hi : c < 0x80 || c > 0xBF) return 0;
  }
  return len;
}

// Whether the sequence s[i, i + len) is a control character: C0 (0x00-0x1F), DEL, or C1
// (U+0080-U+009F, which some terminals obey like ESC + a letter).
inline bool is_control(std::string_view s, size_t i, size_t len) {
  const auto b = static_cast<uint8_t>(s[i]);
  if (len == 1) return b < 0x20 || b == 0x7F;
  return len == 2 && b == 0xC2 && static_cast<uint8_t>(s[i + 1]) <= 0x9F;
}

// What escape_bytes escapes.
//   Json:     ill-formed bytes and NUL (JSON escapes control characters itself);
//   Quote:    ill-formed bytes and every control character;
//   Terminal: control characters but newline and tab, and the ill-formed bytes that are controls
//             to an 8-bit terminal (NUL, 0x80-0x9F: 0x9B is CSI); other bytes stay as they are,
//             so a Latin-1 path prints as the user's terminal shows it.
enum class Mode { Json, Quote, Terminal };

// `s` with the bytes `mode` escapes as the four characters "\xNN" (upper-case hex); stops
// before the sequence that starts at or after byte `max_bytes` of `s`, never inside one.
inline std::string escape_bytes(std::string_view s, Mode mode, size_t max_bytes) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  out.reserve(s.size() < max_bytes ? s.size() : max_bytes);
  for (size_t i = 0; i < s.size() && i < max_bytes;) {
    const size_t len = sequence_length(s, i);
    const auto b = static_cast<uint8_t>(s[i]);
    bool escaped = len == 0;
    if (len > 0 && mode != Mode::Json && is_control(s, i, len))
      escaped = !(mode == Mode::Terminal && (b == '\n' || b == '\t'));
    if (len == 0 && mode == Mode::Terminal) escaped = b == 0 || (b >= 0x80 && b <= 0x9F);
    if (!escaped) {
      const size_t n = len > 0 ? len : 1;
      out.append(s.substr(i, n));
      i += n;
      continue;
    }
    for (const size_t end = i + (len > 0 ? len : 1); i < end; ++i) {
      const auto c = static_cast<uint8_t>(s[i]);
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

}  // namespace utf8_detail

// `s` with every byte that is not part of a well-formed UTF-8 sequence written as the four
// characters "\xNN" (upper-case hex), and every NUL as "\x00". Valid text is unchanged. Chosen
// over U+FFFD replacement because it keeps the bytes recoverable: a run.json names the exact
// folder a user must look for. A backslash already in `s` is left alone, so the escape is for
// reading, not a bijection.
inline std::string escape_invalid_utf8(std::string_view s) {
  return utf8_detail::escape_bytes(s, utf8_detail::Mode::Json, std::string_view::npos);
}

// How much of a quoted input `printable` keeps by default: enough to recognise a value, a
// header line or a token, not a 200 MB one.
constexpr size_t kMaxQuotedBytes = 200;

// `s` as it may be quoted in a message, a log line or a terminal: ill-formed UTF-8 and control
// characters (newlines and terminal escape sequences included) as "\xNN", and only its first
// `max_bytes` bytes, followed by "... (N bytes)" when it is longer. Every message that quotes
// input (a file's line, a YAML value, a reply) quotes it through this.
inline std::string printable(std::string_view s, size_t max_bytes = kMaxQuotedBytes) {
  std::string out = utf8_detail::escape_bytes(s, utf8_detail::Mode::Quote, max_bytes);
  if (s.size() > max_bytes) out += "... (" + std::to_string(s.size()) + " bytes)";
  return out;
}

// A whole message as the command line prints it: its control characters as "\xNN" but its own
// newlines and tabs, raw bytes that an 8-bit terminal obeys (0x80-0x9F) escaped too, other bytes
// as they are; cut after `max_bytes` like printable (by default nothing is cut: the input it
// quotes was capped where it was quoted). The last guard against an escape sequence from a file or
// a param reaching the terminal.
inline std::string terminal_safe(std::string_view s, size_t max_bytes = std::string_view::npos) {
  std::string out = utf8_detail::escape_bytes(s, utf8_detail::Mode::Terminal, max_bytes);
  if (s.size() > max_bytes) out += "... (" + std::to_string(s.size()) + " bytes)";
  return out;
}

// `s` without ANSI terminal escape sequences (ESC '[' parameters final-byte, e.g. the colour codes
// Open3D wraps its error messages in), which mean nothing in a file and garble a terminal later.
inline std::string without_terminal_codes(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\x1b' && i + 1 < s.size() && s[i + 1] == '[') {
      size_t j = i + 2;
      while (j < s.size() && (s[j] < 0x40 || s[j] > 0x7E)) ++j;  // parameter/intermediate bytes
      i = j;                                                     // skip the final byte too
      continue;
    }
    out += s[i];
  }
  return out;
}

}  // namespace gslift
