#pragma once

#include "runtime/registry.hpp"

namespace gslift {

// The detector-priors family (paper 002): fusion.render_semantics, fusion.bayesian,
// fusion.multiview, fusion.cluster_smoothing.
void register_fusion_nodes(Registry& registry);

}  // namespace gslift
