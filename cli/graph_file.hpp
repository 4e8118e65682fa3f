// The graph file a command names: loaded and validated with every diagnostic printed, and the
// run seed it carries.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>

#include "graph/graph.hpp"
#include "graph/loader.hpp"
#include "runtime/registry.hpp"

namespace gslift {

// Loads and validates; prints every diagnostic; nullopt when the graph is invalid. A path that is
// not a regular file (a directory, a FIFO, a symlink loop) is an InputError (exit 4). With
// `printed`, a diagnostic whose text is in it is not printed again and each printed one is added:
// a sweep validates one graph per combination, and the same warning 20 times hides the one that
// differs.
std::optional<Graph> load_checked(const std::string& file, const Registry& registry,
                                  const LoadOptions& opt, std::set<std::string>* printed = nullptr);

// The run seed: the graph's `seed` param (where --seed lands too), else 0.
uint64_t run_seed(const Graph& graph);

}  // namespace gslift
