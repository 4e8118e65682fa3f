// The line-of-sight prior as a loss (issue 11): the differentiable form of the pruning rule in
// free_space.hpp. A training pixel whose depth prior observed a surface at D saw through the space
// in front of it, so the opacity the model accumulates there before reaching (1 - tolerance) D,
//   F_p = 1 - prod_{i in front} (1 - alpha_i),   "in front": camera depth z_i < (1 - tolerance) D,
// is drawn in observed free space (DS-NeRF's line-of-sight / free-space term, Deng et al. 2022, and
// the depth-ordering priors of sparse-view 3DGS). Its gradient reaches what pruning cannot: it
// shrinks, fades or moves the part of a Gaussian's footprint that lies in front of the surface
// (an object's rim reaching past its silhouette) and leaves the part on the surface alone.
#pragma once

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

// L = mean over the pixels with a prior (depth > 0 and finite) of F_p. `forward` is a render of the
// model in this view (any channels; its size is the prior's): its tile lists give each pixel's
// Gaussians in blending order, and its alphas (the same projection, clamp at 0.99, min_alpha and
// early stop) are the ones F is computed from. When grads is given, adds scale * dL/d(means,
// log_scales, quats, opacity_logits) to it (sized for the model); a clamped alpha has none, and
// the depth test is a step, with none. Parallel over tiles: deterministic at any thread count.
double line_of_sight_loss(const GaussianModel& model, const Camera& camera, const Pose& pose,
                          const cv::Mat1f& prior_depth, const RenderOutput& forward,
                          double tolerance, double scale = 1.0, ModelGrads* grads = nullptr);

}  // namespace gslift
