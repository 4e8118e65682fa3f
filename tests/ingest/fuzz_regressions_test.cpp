// Every input a fuzzer crashed on (and the hostile files of issue 16) stays a test: each file in
// tests/data/fuzz_regressions/<target>/ runs through the same target as in fuzz/ (targets.cpp),
// here in the normal build, where success and InputError are the only accepted outcomes.
#include <fstream>

#include "fuzz/targets.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

TEST_CASE("every fuzz regression input is read or refused with InputError", "[hostile]") {
  const fs::path root = test::test_data("fuzz_regressions");
  int files = 0;
  for (const std::string& target : fuzz::target_names()) {
    if (!fs::is_directory(root / target)) continue;
    for (const auto& entry : fs::directory_iterator(root / target)) {
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), {});
      INFO(target << ": " << entry.path().string());
      CHECK_NOTHROW(fuzz::run_target(target, bytes));
      ++files;
    }
  }
  // Every folder names a target (a typo would skip its files silently).
  for (const auto& entry : fs::directory_iterator(root)) {
    const auto& names = fuzz::target_names();
    CHECK(std::find(names.begin(), names.end(), entry.path().filename().string()) != names.end());
  }
  CHECK(files >= 1);
}
