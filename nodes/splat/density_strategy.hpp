// Density control and pruning over a run (the idea of gsplat's Strategy): the training loop hands
// it each step's gradients after the optimiser's update; on its rounds it grows and prunes the
// model (density_control.hpp), with the free-space rules (free_space.hpp) marking what else goes,
// and says how the rows moved so that the optimiser's moments follow them.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "nodes/splat/density_control.hpp"
#include "nodes/splat/free_space.hpp"
#include "nodes/splat/reconstruct.hpp"

namespace gslift {

class DensityStrategy {
 public:
  // `observations` (the training views' depth priors) are borrowed for the run; `extent` scales
  // the density thresholds (reconstruction_extent).
  DensityStrategy(const ReconstructOptions& options, double extent,
                  const std::vector<DepthObservation>& observations);

  // After step `step`'s update: gathers the step's statistics and, on a round, changes the model.
  // Returns the round's change when there was one (feed change.source to the optimiser).
  std::optional<DensityChange> after_update(GaussianModel& model, const ModelGrads& grads,
                                            int step);

  size_t free_space_pruned() const { return free_space_pruned_; }
  size_t growth_refused() const { return growth_refused_; }
  // The round that removed the last Gaussians, when one did.
  const std::optional<ReconstructResult::Emptied>& emptied() const { return emptied_; }

 private:
  // Free-space pruning keeps its rounds after growth stops (floaters can drift in late).
  bool is_free_space_step(int step) const;

  bool densify_;
  DensityControlOptions density_;
  int iterations_;
  bool prune_free_space_;
  double extent_;
  uint64_t seed_;
  const std::vector<DepthObservation>& observations_;
  DensityStats stats_;
  FreeSpacePruner pruner_;
  size_t free_space_pruned_ = 0, growth_refused_ = 0;
  std::optional<ReconstructResult::Emptied> emptied_;
};

}  // namespace gslift
