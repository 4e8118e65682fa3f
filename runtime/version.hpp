// The gslift version recorded in run.json and printed by `gslift --version`.
#pragma once

namespace gslift {

const char* gslift_version();      // project version, "0.1.0"
const char* gslift_git_version();  // `git describe --always --dirty --tags` at configure time

}  // namespace gslift
