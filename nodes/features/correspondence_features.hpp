// SAGA (paper 001 §4.2): per-Gaussian affinity features trained with the correspondence loss
// (correspondence_loss.hpp) from multi-granularity automatic masks, geometry and colour frozen.
// Every iteration takes `views_per_iteration` training views (drawn per iteration), samples
// pixels_per_iteration pixels covered by some mask in each (SAGA: about 1000 rays per step),
// renders their features from the frozen blend weights (pixel_feature_training.hpp) and pairs
// every two of them. Defaults follow SAGA: 32 channels, Adam at 2.5e-3, features initialised as
// N(0, 0.01^2) draws.
//
// Deterministic for a fixed seed at any thread count: the view and the pixels of (iteration,
// batch) come from an RNG seeded by (seed, iteration, batch).
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

// correspondence: the paper's loss (correspondence_loss.hpp). scale_gated: the public v2 code's
// scale-gated contrastive loss (scale_gated_loss.hpp) with K-neighbour smoothing
// (feature_smoothing.hpp) and per-mask 3D scales from rendered depth (mask_scales.hpp); the
// output features are the smoothed ones gated at gate_scale (scale_gated_features.hpp).
enum class AffinityVariant { Correspondence, ScaleGated };
const EnumNames<AffinityVariant>& affinity_variant_names();  // correspondence, scale_gated

struct CorrespondenceOptions {
  AffinityVariant variant = AffinityVariant::Correspondence;
  int iterations = 1000;            // SAGA: 10000 on a GPU; measured in docs/saga.md
  int dim = 32;                     // SAGA feature_dim
  double lr = 2.5e-3;               // SAGA feature_lr
  int pixels_per_iteration = 1000;  // SAGA num_sampled_rays
  int views_per_iteration = 1;      // SAGA: one view per step
  double init_std = 1e-2;           // SAGA: randn * 1e-2
  // Render L2-normalised per-Gaussian features (SAGA's code: norm_point_features = True), so that
  // a pixel's feature is a blend of unit vectors. Off (default) renders the raw features, the
  // paper's formula as written [measured on the embedded OR, click prompts: 36.8 mIoU off, 30.8
  // on (docs/saga.md)].
  bool normalize_gaussians = false;
  // Blend weights below this are left out of the stored rows (as features.contrastive).
  double min_weight = 1e-2;
  // scale_gated only (SAGA v2 code's values): neighbours averaged by the smoothing (smooth_K = 16;
  // half of them per step), weight of the rendered-norm regulariser (rfn = 1), scales sampled per
  // step besides the largest and the smallest (8), the quantile-space scale the output features
  // are gated at (the GUI slider's default 0.5), and the code's row/column swap in the
  // back-projection of the mask scales (kept by default: mask_scales.hpp).
  int smooth_k = 16;
  double norm_weight = 1.0;
  int sampled_scales = 8;
  double gate_scale = 0.5;
  bool scale_swap_axes = true;
  uint64_t seed = 0;  // not a param: the node's seed
};

const ParamTable<CorrespondenceOptions>& correspondence_param_table();

struct CorrespondenceResult {
  GaussianModel model;  // the input geometry, features = the trained N x dim features
  double loss_start = 0, loss_end = 0;  // mean L_corr at the first and the last iteration
  int views = 0;                        // training views with masks
  int masks = 0;                        // masks of those views
  size_t cache_bytes = 0;               // stored per-pixel rows and mask bitsets
  double seconds = 0;
};

// Trains features on the masks of the capture's TRAINING views. Throws InputError when the model
// is empty, no training view has a mask or an option is out of range.
CorrespondenceResult train_correspondence_features(const GaussianModel& model,
                                                   const Capture& capture, const MaskSet& masks,
                                                   const CorrespondenceOptions& options,
                                                   const TrainingProgress& progress = {});

}  // namespace gslift
