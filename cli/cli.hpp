// The gslift command line (docs/cli.md): main() fills a CommandTable (the runtime's commands,
// cli/runtime_commands.hpp, and the programs of node families, cli/program_command.hpp) and
// hands it here with the node registry.
#pragma once

#include "cli/command.hpp"
#include "runtime/registry.hpp"

namespace gslift {

// Runs the command argv[1] names (or --help, --version); maps every failure to its exit code
// (runtime/exit_codes.hpp) with one message. Returns the process exit code.
int cli_main(int argc, char** argv, const Registry& registry, const CommandTable& commands);

}  // namespace gslift
