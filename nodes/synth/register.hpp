#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_synth_nodes(Registry& registry);

}  // namespace gslift
