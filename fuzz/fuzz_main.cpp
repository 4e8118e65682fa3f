// A libFuzzer executable for the target named by GSLIFT_FUZZ_TARGET (fuzz/CMakeLists.txt).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  gslift::fuzz::run_target(GSLIFT_FUZZ_TARGET,
                           std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
