#include "cli/cli.hpp"
#include "cli/runtime_commands.hpp"
#include "tests/runtime/debug_nodes.hpp"

int main(int argc, char** argv) {
  const gslift::Registry registry = gslift::test::debug_registry();
  gslift::CommandTable commands;
  gslift::add_runtime_commands(commands);
  return gslift::cli_main(argc, argv, registry, commands);
}
