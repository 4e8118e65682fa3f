// LangOR §3.2: mask-aware contrastive learning of per-Gaussian instance features
// with the geometry frozen. Each training view's blend weights are recorded once in a RenderCache;
// every iteration samples pixels of each mask, renders their features F(p) = sum_i w_i f_i
// (LangOR Eq. 1) from the cached rows, evaluates LangOR Eq. 3 (contrastive_loss.hpp) and sends
// dL/dF(p) back to the Gaussians through the same weights (the transpose of the product), then
// takes one Adam step on the features only. The loop is train_pixel_features
// (pixel_feature_training.hpp), shared with the other feature objectives on frozen geometry.
//
// Only the sampled pixels are rendered and back-propagated: the full products W f and W^T dL/dF
// of RenderCache cost O(entries of the whole image) per view and iteration; at the defaults the
// samples of the embedded OR (43 training masks x 2 x 128 pixels) are under 1% of its 4 training
// views' pixels. For the same reason only the cache's per-pixel rows are kept, without its
// per-Gaussian transpose, and without blend weights below min_weight.
//
// Measured on the default embedded OR capture (5 views 640x480, 80k Gaussians after
// splat.reconstruct, 300 iterations; "separability" = share of held-out-view pixels whose
// rendered feature is nearest by cosine to the centroid of their own ground-truth instance):
//   min_weight  stored rows  seconds*  separability
//   0           601 MB       38.8      0.959
//   1e-4        500 MB       35.5      0.959
//   1e-3        382 MB       30.6      0.959
//   1e-2        189 MB       23.6      0.959
// (*on the shared 2-core machine at a load average of 8-11: relative numbers only). Keeping the
// whole RenderCache (rows and transpose) held 1.2 GB. Loss per mask 0.83 -> 0.015.
// Learning rate and pixels per mask (min_weight 1e-3; loss end / separability):
//   lr       128 px          256 px          512 px
//   1e-3     0.033 / 0.966   0.031 / 0.966   0.029 / 0.966
//   2.5e-3   0.016 / 0.962   0.015 / 0.959   0.015 / 0.960
//   1e-2     0.011 / 0.947   0.010 / 0.946
// A faster rate fits the training masks better and separates held-out pixels worse (the masks'
// own errors are learnt too): the default is 1e-3, and 128 pixels per mask, as more cost time
// for nothing (seconds roughly proportional to the pixels). At the defaults: 6.9 s (load average
// about 6), 189 MB of rows, loss per mask 0.83 -> 0.035.
//
// Deterministic for a fixed seed at any thread count: the pixels of (iteration, mask) come from
// an RNG seeded by (seed, iteration, mask index), never a thread id, and the per-mask gradients
// are scattered to the Gaussians sequentially in mask order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "base/training_step.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct ContrastiveOptions {
  int iterations = 300;  // LangOR: 300 steps after the 500 of reconstruction
  double lambda = 0.2;   // weight of the repulsion term (LangOR Eq. 3)
  int dim = 16;          // feature channels per Gaussian [decision]
  // Adam learning rate of the features [measured below; 3DGS / LangSplat use 2.5e-3].
  double lr = 1e-3;
  // Pixels sampled per mask and iteration inside the mask, and as many outside it (uniformly over
  // the rest of the view) [decision].
  int pixels_per_iteration = 128;
  // Features start as independent N(0, init_std^2) draws (seeded): small and random so that no
  // two Gaussians start with the same direction.
  double init_std = 0.1;
  // Blend weights below this are left out of the stored rows [decision, measured above: 6x less
  // memory than all weights, same separability].
  double min_weight = 1e-2;
  uint64_t seed = 0;  // not a param: the node's seed
};

// The params of features.contrastive: one entry per field above.
const ParamTable<ContrastiveOptions>& contrastive_param_table();

struct ContrastiveResult {
  GaussianModel model;  // the input geometry, features = the trained N x dim features
  // Mean L_M over the masks (contrastive_loss.hpp) at the first iteration (before any update)
  // and at the last one.
  double loss_start = 0;
  double loss_end = 0;
  int masks = 0;           // non-empty masks of training views that were trained on
  size_t cache_bytes = 0;  // memory of the stored per-pixel rows of all training views
  double seconds = 0;
};

// Called after every iteration with (iteration, total); may throw to stop the run.
using ContrastiveProgress = TrainingProgress;

// Trains features for `model` on the masks of the capture's TRAINING views (masks of held-out
// views are ignored: they are test data). Throws InputError when a ViewMasks names a view the
// capture lacks, a mask's size differs from its view's, the model is empty, no training view has
// a non-empty mask, or an option is out of range.
ContrastiveResult train_contrastive_features(const GaussianModel& model, const Capture& capture,
                                             const MaskSet& masks,
                                             const ContrastiveOptions& options,
                                             const ContrastiveProgress& progress = {});

}  // namespace gslift
