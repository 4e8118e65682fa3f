#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_masks_nodes(Registry& registry);

}  // namespace gslift
