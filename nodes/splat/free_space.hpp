// Multi-view free-space consistency of Gaussians (issue 11's first lever; the idea of the
// multi-view-consistent pruning in fast sparse-view 3DGS recipes): every training view with a
// depth prior says which space is empty, namely the stretch of each pixel's ray in front of the
// surface it observed. A Gaussian whose centre sits in that empty stretch in some training view
// is drawn there as a floater by any other camera, however well it fits the views it was
// trained on (behind a surface, or seen along the ray it blends into, it costs them nothing).
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"

namespace gslift {

// One training view's depth observation (CV_32FC1 metres, 0 or non-finite = none), borrowed.
struct DepthObservation {
  const Camera* camera = nullptr;
  const Pose* pose = nullptr;
  cv::Mat1f depth;
};

// When to prune against the depth priors (0 switches a rule off).
struct FreeSpacePruneOptions {
  // Prune a Gaussian that draws more than this fraction of its training-view weight in observed
  // free space (line_of_sight_weights below).
  double line_of_sight = 0;
  // The line-of-sight rule prunes only a Gaussian that violates it in this many pruning rounds
  // running (1: at once). A Gaussian on its way to its surface crosses free space for a round or
  // two of a short run; a floater stays there (FreeSpacePruner).
  int line_of_sight_rounds = 1;
  // Prune a Gaussian that draws more than this fraction of its training-view weight behind the
  // depth prior (seen through the observed surface: an opaque model would hide it), under the same
  // rounds-running rule as line_of_sight. 0 = off.
  double behind = 0;
  // Prune a Gaussian more than this fraction of whose footprint, summed over the training views,
  // lies behind the depth prior (footprint_behind below: hidden from the cameras), under the same
  // rounds-running rule. 0 = off.
  double hidden = 0;
  // Relative depth tolerance of every test: the depth prior's noise and the Gaussians' extent.
  double tolerance = 0.1;
  // The weight and footprint tests (and reconstruct's line-of-sight loss) take each Gaussian's
  // depth along each pixel's ray (its density maximum there, ray_depth.hpp) instead of its
  // centre's depth: a flat Gaussian of a surface seen at a slant reaches in front of and behind
  // its centre's depth by its extent times the slant, so at the centre's depth the margin above
  // has to cover that as well as the prior's noise (issue 11: bench/splat_recon/README.md).
  bool ray_depth = false;
  bool active() const { return line_of_sight > 0 || behind > 0 || hidden > 0; }
};

// Per Gaussian, its blending weight w_i = alpha_i T_i summed over the pixels of the training views
// that observed a depth D, split by where the Gaussian's camera depth z (its centre's, or with
// ray_depth its depth along the pixel's ray) lies on each pixel's ray:
// `free_space` where z < (1 - tolerance) D (drawn in space that pixel saw through: the
// line-of-sight prior of depth-supervised NeRFs), `on_surface` where not. Unlike a test of the
// centre alone it looks at the whole footprint: an object's Gaussian whose footprint reaches past
// the object's silhouette onto the wall behind draws there in free space although its centre is on
// the object. `behind` is the part of `on_surface` drawn where z > (1 + tolerance) D: seen through
// the surface the pixel observed, which an opaque model would hide. `unobserved` holds the weight
// drawn at pixels without a depth, so free_space + on_surface + unobserved is the Gaussian's whole
// training-view weight (floater_origins reports it). Renders each view once (weights only).
// Deterministic at any thread count.
struct LineOfSightWeights {
  std::vector<double> free_space, on_surface, unobserved, behind;
};
LineOfSightWeights line_of_sight_weights(const GaussianModel& model,
                                         const std::vector<DepthObservation>& views,
                                         double tolerance, bool ray_depth = false);

// 1 for the Gaussians whose free-space weight exceeds `fraction` of their observed weight (free
// space + on surface), or whose weight behind the surface exceeds `behind` of it; 0 = a side off.
std::vector<char> line_of_sight_prune_mask(const LineOfSightWeights& weights, double fraction,
                                           double behind = 0);

// Per Gaussian, its footprint over the pixels of the training views that observed a depth D: the
// sum of its alpha there, with no transmittance (what it would cover if nothing stood in front of
// it), and the part of it where the Gaussian lies behind the observed surface, z > (1 + tolerance)
// D (z as in line_of_sight_weights); both summed over the views. A Gaussian whose footprint lies
// behind the observed surfaces is hidden from the cameras: they cannot place it, and what they see
// of it (a sliver at a silhouette, with the little weight line_of_sight_weights measures, which
// lets it escape the `behind` rule) fits wherever it stands in the space no camera sees, so a new
// camera finds it in front of whatever is there. Summed over the views, not view by view: a
// Gaussian that one view sees edge-on (a few pixels, on its surface) and the others not at all is
// as unconstrained along that view's rays. Renders each view once and visits every tile-list entry,
// past where blending stops. Deterministic at any thread count.
struct FootprintDepth {
  std::vector<double> observed, behind;
};
FootprintDepth footprint_behind(const GaussianModel& model,
                                const std::vector<DepthObservation>& views, double tolerance,
                                bool ray_depth = false);

// The rules above over a run's pruning rounds. The line-of-sight rule's streaks (the rounds
// running in which each Gaussian violated it) live here and follow the model's rows through
// density control.
class FreeSpacePruner {
 public:
  explicit FreeSpacePruner(const FreeSpacePruneOptions& options) : options_(options) {}

  // One pruning round: 1 for the Gaussians that have now violated an active rule
  // `line_of_sight_rounds` rounds running, else 0. Computes only what the active rules need.
  std::vector<char> prune_mask(const GaussianModel& model,
                               const std::vector<DepthObservation>& views);

  // After a density round: row i came from old row source[i]; -1 (a new Gaussian: a clone or a
  // split child) starts without a streak.
  void remap(const std::vector<int>& source);

 private:
  FreeSpacePruneOptions options_;
  std::vector<uint8_t> streak_;
};

}  // namespace gslift
