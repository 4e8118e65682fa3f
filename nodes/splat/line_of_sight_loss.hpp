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

// Two terms, each a mean over the pixels with a prior (depth > 0 and finite):
//   front  = F_p above: the opacity drawn in observed free space;
//   behind = W_p = T_surface - T_end, the weight drawn behind (1 + tolerance) D, where the pixel
//            saw an opaque surface: what the training image shows through a semi-transparent
//            surface. A Gaussian seen only so is free to lie anywhere along the rays behind it,
//            and a camera from elsewhere sees it in front of other surfaces (issue 11: seed 0's
//            blob beside the near cart, 36-40% of the floater Gaussians' training weight).
//            Its gradient fades what is behind and makes the surface in front opaque (the
//            "empty behind the surface" part of the line-of-sight priors of depth-supervised
//            NeRFs). Computed only when behind_scale > 0 (the walk then goes past the surface).
// `forward` is a render of the model in this view (any channels; its size is the prior's): its
// tile lists give each pixel's Gaussians in blending order, and its alphas (the same projection,
// clamp at 0.99, min_alpha and early stop) are the ones the terms are computed from. When grads is
// given, adds front_scale * d front + behind_scale * d behind with respect to (means, log_scales,
// quats, opacity_logits) to it (sized for the model); a clamped alpha has none, and the depth tests
// are steps, with none. Parallel over tiles: deterministic at any thread count.
struct LineOfSightLoss {
  double front = 0, behind = 0;
};
LineOfSightLoss line_of_sight_loss(const GaussianModel& model, const Camera& camera,
                                   const Pose& pose, const cv::Mat1f& prior_depth,
                                   const RenderOutput& forward, double tolerance,
                                   double front_scale = 1.0, double behind_scale = 0.0,
                                   ModelGrads* grads = nullptr);

}  // namespace gslift
