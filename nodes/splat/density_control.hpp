// Adaptive density control (3DGS §5.2, gsplat's DefaultStrategy) rescheduled for short
// sparse-view runs: grow Gaussians where the view-space positional gradient is large (clone the
// small ones, split the large ones), prune transparent and oversized ones, and never exceed a
// Gaussian budget.
//
// [decision] Schedule. 3DGS densifies every 100 steps from step 500 to 15000 of 30000 and resets
// opacity every 3000 steps. LangOR trains 500 iterations from a dense depth initialisation, so
// the defaults here densify every 50 steps from step 100 to 60% of the run (5 rounds in 500
// iterations: statistics need ~50 steps, ~10 passes over 5 views, to mean anything) and never
// reset opacity (a reset needs thousands of steps to recover). bench/splat_recon measures it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "nodes/scene/gaussian_model.hpp"

namespace gslift {

struct DensityControlOptions {
  int start = 100;                   // first densification step
  double stop = 0.6;                 // last densification step, as a fraction of the iterations
  int interval = 50;                 // steps between densification rounds
  double grad_threshold = 2e-4;      // mean NDC gradient norm of the 2D mean that triggers growth
  double clone_max_scale = 0.01;     // x scene extent: clone when the largest scale is at most this
  int split_children = 2;            // a split replaces a Gaussian by this many samples from it
  double split_scale_divisor = 1.6;  // children's scales are the parent's divided by this (3DGS)
  double prune_opacity = 0.005;      // prune when sigmoid(opacity logit) is below this
  double prune_max_scale = 0.1;      // x scene extent: prune when the largest scale exceeds this
  size_t max_gaussians = 200000;     // budget; growth stops (largest gradients first) at it
};

// Per-Gaussian accumulators between densification rounds (3DGS xyz_gradient_accum, denom).
struct DensityStats {
  std::vector<double> grad_sum;  // sum over visible views of |dL/d mean2d| (NDC)
  std::vector<int> visible;      // number of views that saw the Gaussian

  // Adds one backward pass's statistics (ModelGrads::mean2d_abs and ::visible), growing as needed.
  void add(const std::vector<float>& mean2d_abs, const std::vector<int32_t>& seen);
  void clear() { grad_sum.clear(), visible.clear(); }
  // Row i becomes old row source[i] (DensityChange::source; -1 = a new Gaussian, zero), so the
  // statistics follow the Gaussians through a prune between densification rounds.
  void remap(const std::vector<int>& source);
};

struct DensityChange {
  // New row i of the model came from old row source[i]; -1 for a new Gaussian (zero Adam moments,
  // as 3DGS's densification_postfix gives new Gaussians). Feed it to AdamGroup::remap.
  std::vector<int> source;
  size_t cloned = 0, split = 0, pruned = 0;
  // Why the pruned went, each counted under its first reason: opacity below prune_opacity, a
  // scale above prune_max_scale x extent, or marked by the caller (free-space pruning).
  size_t pruned_opacity = 0, pruned_scale = 0, pruned_marked = 0;
  size_t refused = 0;  // growth candidates the Gaussian budget left out (max_gaussians reached)
};

// True when `step` (0-based, after the step's update) is a densification round.
bool is_density_step(const DensityControlOptions& options, int step, int iterations);

// One round on the model in place. Order: kept Gaussians in their order, then clones, then split
// children. A Gaussian that is both pruned and selected for growth is pruned. Split children are
// sampled from the parent's Gaussian with an RNG seeded by (seed, parent index), so the result
// does not depend on thread count or on which other Gaussians split. extent is the scene radius
// (3DGS: 1.1 x the largest camera distance from the cameras' centroid). Gaussians marked in
// also_prune (empty = none; free_space.hpp) are pruned as well.
DensityChange densify_and_prune(GaussianModel& model, const DensityStats& stats,
                                const DensityControlOptions& options, double extent, uint64_t seed,
                                const std::vector<char>& also_prune = {});

}  // namespace gslift
