// An optional per-Gaussian feature objective trained together with the reconstruction: the
// joint training of Proto-SaGa (paper 000, Eq. 8: L = L_rec + lambda_CE L_CE), where the
// geometry also receives the gradient of the feature loss. reconstruct() owns the features (dim
// channels per Gaussian, rendered in the colour pass, stepped by their own Adam group and carried
// through densification like any other attribute); the caller owns what the loss means (labels,
// classifiers, sampling) through two callbacks. Without an objective reconstruct() is unchanged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "nodes/splat/rasterizer.hpp"

namespace gslift {

struct FeatureObjective {
  int dim = 0;         // feature channels per Gaussian
  double weight = 0;   // lambda: L = L_rec + weight L_feat (Proto-SaGa lambda_CE = 0.05)
  double lr = 2.5e-3;  // Adam rate of the features (Proto-SaGa 2.5e-3)
  // Fills the initial features of the n Gaussians the initialisation made (n x dim, sized).
  std::function<void(size_t n, std::vector<float>& features)> initialise;
  // L_feat at one training step: `view` indexes capture.views, `rendered` is that view's feature
  // image (height x width x dim; the step's resolution, half the camera's in coarse steps). Writes
  // dL_feat/dF into `grad` (same layout, zeroed by the caller) and returns L_feat. Called once per
  // step, in step order; the caller may keep gradients of its own parameters for `update`.
  std::function<double(int step, int view, int width, int height, const float* rendered,
                       float* grad)>
      loss;
  // Optional: the pixels (row-major, of the width x height render) that `loss` will read at this
  // step, asked before the render. The forward pass then blends features only near them
  // (RenderSettings::feature_pixels): `rendered` is exact there and may be 0 elsewhere.
  std::function<void(int step, int view, int width, int height, std::vector<uint32_t>& pixels)>
      pixels;
  // Optional: steps the caller's own parameters (e.g. classifiers) after the model's Adam step.
  std::function<void(int step)> update;
};

// The feature part of one training step: evaluates objective.loss on `forward`'s features and
// sets grads.features = weight x dL_feat/dF, which render_backward adds to the colour pass's
// gradients. Returns L_feat (unweighted).
double feature_objective_grads(const FeatureObjective& objective, int step, int view,
                               const RenderOutput& forward, RenderGrads& grads);

}  // namespace gslift
