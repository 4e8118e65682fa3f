#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_text_nodes(Registry& registry);

}  // namespace gslift
