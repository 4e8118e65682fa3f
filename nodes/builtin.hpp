#pragma once

#include "runtime/registry.hpp"

namespace gslift {

// Adds every node type that ships with gslift. One visible list (nodes/builtin.cpp): a node type
// exists exactly when its family's register function adds it.
void register_builtin_nodes(Registry& registry);

}  // namespace gslift
