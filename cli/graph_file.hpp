// The graph file a command names: loaded and validated with every diagnostic printed, and the
// run seed it carries.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "graph/graph.hpp"
#include "graph/loader.hpp"
#include "runtime/registry.hpp"

namespace gslift {

// Loads and validates; prints every diagnostic; nullopt when the graph is invalid. A path that is
// not a regular file (a directory, a FIFO, a symlink loop) is an InputError (exit 4).
std::optional<Graph> load_checked(const std::string& file, const Registry& registry,
                                  const LoadOptions& opt);

// The run seed: the graph's `seed` param (where --seed lands too), else 0.
uint64_t run_seed(const Graph& graph);

}  // namespace gslift
