// The Catch2 main shared by every test executable: Catch's own session, with one change to the
// exit code. A process whose test skipped (tests/test_skip.hpp) and failed nothing exits with
// kSkipReturnCode; a failing one never does (Catch returns the number of failed assertions).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "tests/test_skip.hpp"

int main(int argc, char** argv) {
  const int failed = Catch::Session().run(argc, argv);
  if (failed == 0 && gslift::test::skipped_flag()) return gslift::test::kSkipReturnCode;
  return failed == gslift::test::kSkipReturnCode ? failed + 1 : failed;
}
