// LangOR §3.2 (METHODS §1.2): mask-aware contrastive learning of per-Gaussian instance features
// with the geometry frozen. Each training view's blend weights are recorded once in a RenderCache;
// every iteration samples pixels of each mask, renders their features F(p) = sum_i w_i f_i
// (LangOR Eq. 1) from the cached rows, evaluates LangOR Eq. 3 (contrastive_loss.hpp) and sends
// dL/dF(p) back to the Gaussians through the same weights (the transpose of the product), then
// takes one Adam step on the features only.
//
// Only the sampled pixels are rendered and back-propagated: the full product W f and W^T dL/dF
// of RenderCache cost O(entries of the whole image) per view and iteration, about 40x more than
// the samples at the defaults on a 640x480 view.
//
// Deterministic for a fixed seed at any thread count: the pixels of (iteration, mask) come from
// an RNG seeded by (seed, iteration, mask index), never a thread id, and the per-mask gradients
// are scattered to the Gaussians sequentially in mask order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"

namespace gslift {

struct ContrastiveOptions {
  int iterations = 300;  // LangOR: 300 steps after the 500 of reconstruction
  double lambda = 0.2;   // weight of the repulsion term (LangOR Eq. 3)
  int dim = 16;          // feature channels per Gaussian [decision, METHODS §1.2]
  double lr = 2.5e-3;    // Adam learning rate of the features (3DGS / LangSplat feature rate)
  // Pixels sampled per mask and iteration inside the mask, and as many outside it (uniformly over
  // the rest of the view) [decision, METHODS §1.2].
  int pixels_per_iteration = 256;
  // Features start as independent N(0, init_std^2) draws (seeded): small and random so that no
  // two Gaussians start with the same direction.
  double init_std = 0.1;
  uint64_t seed = 0;
};

struct ContrastiveResult {
  GaussianModel model;  // the input geometry, features = the trained N x dim features
  // Mean L_M over the masks (contrastive_loss.hpp) at the first iteration (before any update)
  // and at the last one.
  double loss_start = 0;
  double loss_end = 0;
  int masks = 0;           // non-empty masks of training views that were trained on
  size_t cache_bytes = 0;  // memory of all render caches together
  double seconds = 0;
};

// Called after every iteration with (iteration, total); may throw to stop the run.
using ContrastiveProgress = std::function<void(int, int)>;

// Trains features for `model` on the masks of the capture's TRAINING views (masks of held-out
// views are ignored: they are test data). Throws InputError when a ViewMasks names a view the
// capture lacks, a mask's size differs from its view's, the model is empty, no training view has
// a non-empty mask, or an option is out of range.
ContrastiveResult train_contrastive_features(const GaussianModel& model, const Capture& capture,
                                             const MaskSet& masks,
                                             const ContrastiveOptions& options,
                                             const ContrastiveProgress& progress = {});

}  // namespace gslift
