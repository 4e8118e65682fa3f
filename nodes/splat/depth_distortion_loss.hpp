// Depth distortion (issue 11): Mip-NeRF 360's distortion loss (Barron et al. 2022, Eq. 15) in the
// form 2DGS gives it for Gaussians (Huang et al. 2024, Eq. 13): per pixel,
//   L_p = sum_i sum_j w_i w_j |u_i - u_j|,   w_i = alpha_i T_i the blending weights,
// small when a ray's weight is spent on one thin layer. Here u = log z, the Gaussian's camera depth
// on a log scale, so that a layer's thickness counts relative to its depth (as the depth prior's
// noise and every margin here do) and the loss has no unit. A surface that a few training views
// with noisy priors see comes out as a layer several centimetres thick, whose back half shows past
// the object's silhouette to a camera looking from the side: the held-out floaters at object
// edges (bench/splat_recon/README.md). The loss needs no prior: it pulls each ray's weight onto
// one layer, fading or moving what lies in front of or behind it.
#pragma once

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

// The mean of L_p over the pixels of `forward`, a render of the model in this view (any channels):
// its tile lists, alphas (clamp at 0.99, min_alpha) and early stop give each pixel's w_i, in the
// lists' depth order, so that L_p = 2 sum_j w_j (u_j A_j - U_j) with A_j, U_j the sums of w and w u
// in front of j. When grads is given, adds scale * dL/d(means, log_scales, quats, opacity_logits)
// to it (sized for the model): through each alpha (a clamped alpha has none) and through each
// Gaussian's depth. Parallel over tiles: deterministic at any thread count.
double depth_distortion_loss(const GaussianModel& model, const Camera& camera, const Pose& pose,
                             const RenderOutput& forward, double scale = 1.0,
                             ModelGrads* grads = nullptr);

}  // namespace gslift
