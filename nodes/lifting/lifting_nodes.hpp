// Node adapters of the lifting family: lifting.cvp (LangOR CVP lifting, Eq. 4-5) and
// lifting.mask_level (its "w/o CVP-L" ablation). Both read model + capture + masks and write
// instances:LiftedInstances, so swapping one for the other in a graph is one line.
#pragma once

#include "runtime/registry.hpp"

namespace gslift {

void add_lifting_nodes(Registry& registry);

}  // namespace gslift
