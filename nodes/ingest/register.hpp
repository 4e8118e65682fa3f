#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void register_ingest_nodes(Registry& registry);

}  // namespace gslift
