#include "runtime/cli.hpp"

#include <cstdio>

namespace gslift {

int cli_main(int, char**, const Registry& registry) {
  for (const auto& t : registry.types()) std::printf("%s\n", t.c_str());
  return 0;
}

}  // namespace gslift
