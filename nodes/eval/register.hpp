#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_eval_nodes(Registry& registry);

}  // namespace gslift
