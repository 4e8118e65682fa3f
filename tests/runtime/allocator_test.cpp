#include "runtime/allocator.hpp"

#include <sys/resource.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/test_skip.hpp"

namespace {

long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

// Allocates and writes 64 blocks of 1 MB (a training step's buffers), frees them all, and returns
// the minor page faults that took.
long faults_of_one_step() {
  const long before = minor_faults();
  std::vector<char*> blocks;
  for (int i = 0; i < 64; ++i) {
    char* p = static_cast<char*>(std::malloc(1u << 20));
    REQUIRE(p != nullptr);
    std::memset(p, 1, 1u << 20);
    blocks.push_back(p);
  }
  for (char* p : blocks) std::free(p);
  return minor_faults() - before;
}

}  // namespace

// g++ defines __SANITIZE_ADDRESS__ under -fsanitize=address; clang answers __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define GSLIFT_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GSLIFT_UNDER_ASAN 1
#endif
#endif

#if defined(__GLIBC__)
TEST_CASE("after keep_freed_memory_in_process a second step reuses the first step's pages",
          "[runtime]") {
#if defined(GSLIFT_UNDER_ASAN)
  // AddressSanitizer replaces malloc with its own allocator (freed blocks go to its quarantine),
  // so glibc's settings that keep_freed_memory_in_process changes do not apply.
  WARN("SKIPPED: AddressSanitizer replaces glibc's malloc");
  gslift::test::mark_skipped();
  return;
#endif
  gslift::keep_freed_memory_in_process();
  faults_of_one_step();
  // 64 MB is 16384 pages. With glibc's defaults the freed heap top is trimmed back to the kernel
  // (its trim threshold is at most twice the largest mmapped block freed so far) and the second
  // step faults all 16384 pages in again.
  CHECK(faults_of_one_step() < 1000);
}
#endif
