// How a test says "skipped" to ctest: it marks the process (mark_skipped), and the shared Catch
// main (tests/catch_main.cpp) then exits with kSkipReturnCode, which tests/CMakeLists.txt registers
// as every test's SKIP_RETURN_CODE. A test that skips is then listed as "Skipped", not "Passed".
#pragma once

#include <atomic>

namespace gslift::test {

constexpr int kSkipReturnCode = 4;

inline std::atomic<bool>& skipped_flag() {
  static std::atomic<bool> skipped{false};
  return skipped;
}

inline void mark_skipped() {
  skipped_flag() = true;
}

}  // namespace gslift::test
