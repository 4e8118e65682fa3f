// The command line of a `gslift run` child of batch or sweep, which run each capture or point as
// its own process (runtime/child_process.hpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "cli/options.hpp"

namespace gslift {

// `graph_file` into `out` with the parent's thread count and cache options, logging at
// `log_level`; the caller adds --input, --seed and --set.
std::vector<std::string> child_run_command(const Args& args, const std::string& graph_file,
                                           const std::filesystem::path& out,
                                           const std::string& log_level);

}  // namespace gslift
