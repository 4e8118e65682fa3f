#pragma once

#include "runtime/registry.hpp"

namespace gslift {

// Adds every node type that ships with gslift, and the binary forms of the port types that the
// stage cache stores. One visible list (nodes/builtin.cpp): a node type
// exists exactly when its family's register function adds it.
void register_builtin_nodes(Registry& registry);

}  // namespace gslift
