#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_association_nodes(Registry& registry);

}  // namespace gslift
