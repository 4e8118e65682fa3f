// The rendered instance-feature maps F(p) (LangOR Eq. 1) of the training views that carry 2D
// masks: the input that lifting (Eq. 4-5) and association (§1.3 "Matching") share. Only TRAINING
// views are rendered; masks of held-out views are never used, so evaluation stays honest.
#pragma once

#include <vector>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/feature_map.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"

namespace gslift {

// The training views of a MaskSet, each with its feature map; maps[i] goes with masks.views[i].
struct TrainingFeatureMaps {
  // For each kept view: its index in the input MaskSet's views and in the capture's views.
  std::vector<int> mask_views;
  std::vector<int> capture_views;
  MaskSet masks;                 // the kept views' masks (copies share the pixel buffers)
  std::vector<FeatureMap> maps;  // rendered F(p), feature_dim channels
  // Per Gaussian (model.size()), when requested: sum over the kept views and their pixels of its
  // blend weight w_i(p) = alpha_i T_i, i.e. how much of the training images it explains.
  std::vector<float> contribution;
};

// Keeps the views of `masks` that are training views of `capture` (training_mask_views, which
// also checks the masks against the capture) and renders the model's features there
// (F(p) = sum_i w_i f_i, Eq. 1); the contribution is each view's W^T 1 (add_blend_weights).
// Throws InputError when the model has no feature channels or training_mask_views does.
TrainingFeatureMaps render_training_feature_maps(const GaussianModel& model, const Capture& capture,
                                                 const MaskSet& masks, bool with_contribution);

}  // namespace gslift
