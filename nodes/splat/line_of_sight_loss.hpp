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

// The opacity each training pixel p with a prior (depth D_p > 0 and finite) accumulates before its
// ray reaches depth_factor x D_p, F_p = 1 - prod_{i: z_i < depth_factor D_p} (1 - alpha_i), and its
// mean over those pixels (0 when the view has none; `observed` receives their count). `forward`
// is a render of the model in this view (any channels; its size is the prior's): its tile lists
// give each pixel's Gaussians in blending order, and its alphas (the same projection, clamp at
// 0.99, min_alpha and early stop) are the ones F is computed from. When grads is given, adds
// scale * d(mean F)/d(means, log_scales, quats, opacity_logits) to it (sized for the model); a
// clamped alpha has none, and the depth test is a step, with none. Parallel over tiles:
// deterministic at any thread count. With ray_depth, z_i is each Gaussian's depth along the
// pixel's ray (ray_depth.hpp) instead of its centre's. The loss below is this at the near end of
// the margin.
double opacity_before_prior(const GaussianModel& model, const Camera& camera, const Pose& pose,
                            const cv::Mat1f& prior_depth, const RenderOutput& forward,
                            double depth_factor, double scale = 1.0, ModelGrads* grads = nullptr,
                            size_t* observed = nullptr, bool ray_depth = false);

// The line-of-sight loss: L = mean F_p at depth_factor 1 - tolerance, the opacity drawn in front of
// the observed surface.
double line_of_sight_loss(const GaussianModel& model, const Camera& camera, const Pose& pose,
                          const cv::Mat1f& prior_depth, const RenderOutput& forward,
                          double tolerance, double scale = 1.0, ModelGrads* grads = nullptr,
                          bool ray_depth = false);

}  // namespace gslift
