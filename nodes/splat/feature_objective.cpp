#include "nodes/splat/feature_objective.hpp"

#include "base/errors.hpp"

namespace gslift {

double feature_objective_grads(const FeatureObjective& objective, int step, int view,
                               const RenderOutput& forward, RenderGrads& grads) {
  if (forward.feature_dim != objective.dim || !objective.loss)
    throw InputError("feature objective: the render has " + std::to_string(forward.feature_dim) +
                     " feature channels, the objective " + std::to_string(objective.dim));
  std::vector<float>& g = grads.features;
  g.assign(forward.features.size(), 0.f);
  const double loss =
      objective.loss(step, view, forward.width, forward.height, forward.features.data(), g.data());
  const float w = static_cast<float>(objective.weight);
  for (float& v : g) v *= w;
  return loss;
}

}  // namespace gslift
