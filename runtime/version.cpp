#include "runtime/version.hpp"

namespace gslift {

// Both are compile definitions of this library (runtime/CMakeLists.txt).
const char* gslift_version() {
  return GSLIFT_VERSION;
}
const char* gslift_git_version() {
  return GSLIFT_GIT_VERSION;
}

}  // namespace gslift
