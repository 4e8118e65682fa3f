#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_lifting_nodes(Registry& registry);

}  // namespace gslift
