#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_inference_nodes(Registry& registry);

}  // namespace gslift
