#pragma once

#include "runtime/registry.hpp"

namespace gslift {

// The gslift command line (README "Command line"). Returns the process exit code.
int cli_main(int argc, char** argv, const Registry& registry);

}  // namespace gslift
