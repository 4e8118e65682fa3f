#pragma once

#include "runtime/registry.hpp"

namespace gslift {

// vlm.query: the live multi-round VLM perceptor (docs/vlm_query.md).
void register_vlm_nodes(Registry& registry);

}  // namespace gslift
