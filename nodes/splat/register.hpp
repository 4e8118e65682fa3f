#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_splat_nodes(Registry& registry);

}  // namespace gslift
