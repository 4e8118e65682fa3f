// One line of a CSV file the benchmarks read (matches.csv, results.csv): the reverse of
// base/csv_field.hpp.
#pragma once

#include <string>
#include <vector>

namespace gslift::bench {

// Fields split at commas outside double quotes ("" inside quotes is a quote), CR dropped.
inline std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
      out.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  return out;
}

}  // namespace gslift::bench
