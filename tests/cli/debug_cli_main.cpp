#include "cli/cli.hpp"
#include "tests/runtime/debug_nodes.hpp"

int main(int argc, char** argv) {
  const gslift::Registry registry = gslift::test::debug_registry();
  return gslift::cli_main(argc, argv, registry);
}
