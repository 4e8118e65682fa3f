// Shared helpers for the Catch2 tests.
#pragma once

#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <catch2/catch.hpp>

#include "tests/test_skip.hpp"

namespace gslift::test {

inline std::filesystem::path test_data(const std::string& rel = {}) {
  return std::filesystem::path(GSLIFT_TEST_DATA) / rel;
}

// The real scenes: ../shared/data beside the checkout, or the folder named by the environment
// variable GSLIFT_SHARED_DATA when it is set (pointing it at a missing folder shows which tests
// skip without the data).
inline std::filesystem::path shared_data(const std::string& rel = {}) {
  const char* env = std::getenv("GSLIFT_SHARED_DATA");
  return std::filesystem::path(env && *env ? env : GSLIFT_SHARED_DATA) / rel;
}

// This process's own scratch root: a fresh mkdtemp folder under the system temp folder, so that
// two checkouts (or two ctest -j runs) testing at once never write into each other's folders. It
// is removed when the process exits, unless GSLIFT_KEEP_SCRATCH is set (to inspect a failure).
class ScratchRoot {
 public:
  ScratchRoot() {
    std::string pattern = (std::filesystem::temp_directory_path() / "gslift_tests_XXXXXX").string();
    if (!::mkdtemp(pattern.data()))
      throw std::runtime_error("cannot create a scratch folder from " + pattern);
    path_ = pattern;
  }
  ~ScratchRoot() {
    if (std::getenv("GSLIFT_KEEP_SCRATCH")) return;
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline const std::filesystem::path& scratch_root() {
  static const ScratchRoot root;
  return root.path();
}

// A fresh, empty scratch folder for one test, inside this process's scratch_root().
inline std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = scratch_root() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace gslift::test

// Skips the rest of a test (with a visible message, and ctest's "Skipped": tests/test_skip.hpp)
// when ../shared/data is not beside the checkout, as on a user's machine; CI has it.
#define GSLIFT_REQUIRE_SHARED_DATA(rel)                                               \
  do {                                                                                \
    if (!std::filesystem::exists(gslift::test::shared_data(rel))) {                   \
      WARN("SKIPPED: " << gslift::test::shared_data(rel).string()                     \
                       << " is absent (../shared/data is only beside CI checkouts)"); \
      gslift::test::mark_skipped();                                                   \
      return;                                                                         \
    }                                                                                 \
  } while (0)
