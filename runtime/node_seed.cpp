#include "runtime/node_seed.hpp"

namespace gslift {

uint64_t node_seed(uint64_t run_seed, std::string_view node_id) {
  return splitmix64(splitmix64(run_seed) ^ fnv1a64(node_id));
}

}  // namespace gslift
