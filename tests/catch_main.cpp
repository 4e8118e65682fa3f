// The Catch2 main shared by every test executable: Catch's own session, with one change to the
// exit code. A process whose test skipped (tests/test_skip.hpp) and failed nothing exits with
// kSkipReturnCode; a failing one never does (Catch returns the number of failed assertions).
//
// Every gslift process a test starts shares the test process's own stage cache, inside its scratch
// root: never the user's ~/.cache/gslift, and never a cache left by an earlier test run (a test
// that interrupts a long node must find the node running, not loaded).
#define CATCH_CONFIG_RUNNER
#include <stdlib.h>

#include <catch2/catch.hpp>

#include "tests/test_skip.hpp"
#include "tests/test_support.hpp"

int main(int argc, char** argv) {
  ::setenv("GSLIFT_STAGE_CACHE", (gslift::test::scratch_root() / "stage-cache").c_str(), 1);
  const int failed = Catch::Session().run(argc, argv);
  if (failed == 0 && gslift::test::skipped_flag()) return gslift::test::kSkipReturnCode;
  return failed == gslift::test::kSkipReturnCode ? failed + 1 : failed;
}
