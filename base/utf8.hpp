// Paths and messages are bytes: a folder with a Latin-1 name, a graph param with a stray byte or
// an error message quoting a binary file are not UTF-8, while JSON strings must be. Standard
// library only, like everything in base/.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gslift {

// `s` with every byte that is not part of a well-formed UTF-8 sequence (RFC 3629: no overlong
// forms, no surrogates, nothing above U+10FFFF) written as the four characters "\xNN" (upper-case
// hex), and every NUL as "\x00". Valid text is unchanged. Chosen over U+FFFD replacement because
// it keeps the bytes recoverable: a run.json names the exact folder a user must look for. A
// backslash already in `s` is left alone, so the escape is for reading, not a bijection.
inline std::string escape_invalid_utf8(std::string_view s) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  out.reserve(s.size());
  const auto byte = [&](size_t i) { return static_cast<uint8_t>(s[i]); };
  const auto escape = [&](uint8_t b) {
    out += "\\x";
    out += hex[b >> 4];
    out += hex[b & 15];
  };
  for (size_t i = 0; i < s.size();) {
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
    bool ok = len > 0 && i + len <= s.size();
    for (size_t k = 1; ok && k < len; ++k) {
      const uint8_t c = byte(i + k);
      ok = k == 1 ? c >= lo && c <= hi : c >= 0x80 && c <= 0xBF;
    }
    if (!ok) {
      escape(b);
      ++i;
      continue;
    }
    out.append(s.substr(i, len));
    i += len;
  }
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
