#include "nodes/splat/density_strategy.hpp"

#include <algorithm>

namespace gslift {

DensityStrategy::DensityStrategy(const ReconstructOptions& options, double extent,
                                 const std::vector<DepthObservation>& observations)
    : densify_(options.densify),
      density_(options.density),
      iterations_(options.iterations),
      prune_free_space_(options.floaters.active() && !observations.empty()),
      extent_(extent),
      seed_(options.seed),
      observations_(observations),
      pruner_(options.floaters) {}

bool DensityStrategy::is_free_space_step(int step) const {
  const DensityControlOptions& d = density_;
  return prune_free_space_ && d.interval > 0 && step >= d.start &&
         (step - d.start) % d.interval == 0;
}

std::optional<DensityChange> DensityStrategy::after_update(GaussianModel& model,
                                                           const ModelGrads& grads, int step) {
  if (!densify_) return std::nullopt;
  stats_.add(grads.mean2d_abs, grads.visible);
  const bool density_step = is_density_step(density_, step, iterations_);
  const bool free_space_step = is_free_space_step(step);
  if (!density_step && !free_space_step) return std::nullopt;
  std::vector<char> marked;
  if (free_space_step) marked = pruner_.prune_mask(model, observations_);
  free_space_pruned_ += std::count(marked.begin(), marked.end(), 1);
  // Outside density rounds no statistics are passed: pruning only, no growth.
  DensityChange change = densify_and_prune(model, density_step ? stats_ : DensityStats{}, density_,
                                           extent_, seed_ + step, marked);
  growth_refused_ += change.refused;
  if (model.size() == 0 && !emptied_)
    emptied_ = ReconstructResult::Emptied{step, change.pruned_opacity, change.pruned_scale,
                                          change.pruned_marked};
  pruner_.remap(change.source);
  if (density_step)
    stats_.clear();
  else
    stats_.remap(change.source);
  return change;
}

}  // namespace gslift
