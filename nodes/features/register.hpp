#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_features_nodes(Registry& registry);

}  // namespace gslift
