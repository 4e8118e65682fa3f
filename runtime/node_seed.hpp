// Per-node random seeds. Derived from (run seed, node id) only, never from thread ids or
// scheduling order, so a node draws the same numbers whatever the thread count, and two nodes of
// one run draw different streams.
#pragma once

#include <cstdint>
#include <string_view>

#include "base/hash.hpp"

namespace gslift {

// The seed a node sees as ctx.seed(): splitmix64(splitmix64(run_seed) ^ fnv1a64(node_id)).
uint64_t node_seed(uint64_t run_seed, std::string_view node_id);

}  // namespace gslift
