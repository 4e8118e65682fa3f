// Shared helpers for the Catch2 tests.
#pragma once

#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

namespace gslift::test {

inline std::filesystem::path test_data(const std::string& rel = {}) {
  return std::filesystem::path(GSLIFT_TEST_DATA) / rel;
}

inline std::filesystem::path shared_data(const std::string& rel = {}) {
  return std::filesystem::path(GSLIFT_SHARED_DATA) / rel;
}

// A fresh, empty scratch folder for one test.
inline std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / "gslift_tests" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace gslift::test

// Skips the rest of a test (with a visible message) when ../shared/data is not beside the
// checkout, as on a user's machine; CI has it.
#define GSLIFT_REQUIRE_SHARED_DATA(rel)                                               \
  do {                                                                                \
    if (!std::filesystem::exists(gslift::test::shared_data(rel))) {                   \
      WARN("SKIPPED: " << gslift::test::shared_data(rel).string()                     \
                       << " is absent (../shared/data is only beside CI checkouts)"); \
      return;                                                                         \
    }                                                                                 \
  } while (0)
