#include "nodes/builtin.hpp"
#include "runtime/cli.hpp"

int main(int argc, char** argv) {
  gslift::Registry registry;
  gslift::register_builtin_nodes(registry);
  return gslift::cli_main(argc, argv, registry);
}
