// Numbers written into CSV and Markdown tables with two decimals.
#pragma once

#include <cstdio>
#include <string>

namespace gslift {

// "%.2f": locale-independent in the "C" locale gslift runs in.
inline std::string fixed2(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f", v);
  return buf;
}

}  // namespace gslift
