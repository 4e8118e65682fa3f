#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_boxes_nodes(Registry& registry);

}  // namespace gslift
