// SAGA's affinity features as the public v2 code trains them (train_contrastive_feature.py;
// ../shared/reference/method-anchors.md §1.3): the `scale_gated` variant of
// features.correspondence. Per training view the masks' 3D scales come from the rendered depth
// (mask_scales.hpp), and one quantile transform (sklearn's QuantileTransformer, uniform output,
// min(1000, n) quantiles) over all of them maps scales to [0, 1]. Every step, per view drawn:
//  - the masks sorted by scale, descending; `sampled_scales` random ones, plus one above the
//    largest (upper (1 + U), then jittered down towards the second largest) and the smallest;
//    each scale jittered uniformly between its mask's scale and the next smaller one (the smallest
//    towards 0);
//  - the ground truth at scale s: masks with scale >= s made exclusive (a pixel goes to the
//    smallest of them that holds it), masks below s kept whole; gt(p, q) = 1 when p and q share a
//    mask; above the largest scale the raw masks;
//  - the pixels (pixels_per_iteration, drawn among the pixels some mask covers) and their pair
//    weights from the mean area of the masks covering each (scale_gated_pair_weights);
//  - rendered features of the smoothed, L2-normalised per-Gaussian features (feature_smoothing,
//    a random half of the smooth_k neighbour slots per step; norm_point_features), the loss
//    scale_gated_loss.hpp, and its gradient back through the weights, the normalisation and the
//    smoothing; Adam at `lr` on the features and on the gate Linear(1, D) (initialised as torch
//    does: U(-1, 1) for a fan-in of 1).
// The output features are the full-K smoothed, normalised features multiplied by the gate at
// gate_scale (quantile space): the gate is a per-channel factor, so rendering them and comparing
// normalised features is SAGA's inference at that scale, and inference.prompt needs no gate.
//
// The code draws its pixels by a Bernoulli trial per pixel at rate 1000 / (H W) among the
// covered pixels; gslift draws pixels_per_iteration of them, as the correspondence variant does,
// and evaluates the norm regulariser over the sampled pixels rather than the whole image.
#pragma once

#include "base/training_step.hpp"
#include "nodes/features/correspondence_features.hpp"

namespace gslift {

// Called by train_correspondence_features for variant scale_gated (same contract).
CorrespondenceResult train_scale_gated_features(const GaussianModel& model, const Capture& capture,
                                                const MaskSet& masks,
                                                const CorrespondenceOptions& options,
                                                const TrainingProgress& progress);

// sklearn's QuantileTransformer(output_distribution="uniform") fitted on `values`: maps a value
// to [0, 1] by linear interpolation between min(1000, n) quantiles (ties averaged both ways).
class QuantileMap {
 public:
  explicit QuantileMap(std::vector<float> values);
  float operator()(float x) const;

 private:
  std::vector<double> quantiles_, references_;
};

}  // namespace gslift
