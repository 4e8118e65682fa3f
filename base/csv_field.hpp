// One CSV field as RFC 4180 writes it (eval tables, sweep results): quoted when it holds a comma,
// a quote or a line break, quotes doubled inside. Class names, params and capture paths come
// from users' files and may hold any of them.
#pragma once

#include <string>

namespace gslift {

inline std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace gslift
