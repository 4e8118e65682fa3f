// Silhouette overhang along the training rays (issue 11): a Gaussian of an object that sits at a
// depth discontinuity of some training view's depth prior, on its near side, is seen by that
// view at the object's silhouette. Its extent along that view's ray (the standard deviation
// sqrt(d^T Sigma d) along the unit ray d) is invisible to the view: edge-on, a disc may stretch
// towards or away from the camera for free. From another camera that stretch is a rim past the
// object, over space the object hides from every training view (80-84% of the held-out floater
// pixels, bench/splat_recon/README.md). This term charges those Gaussians for that extent; only
// their scales pay (means and rotations keep their photometric gradients).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/free_space.hpp"

namespace gslift {

// Per view, the pixels within `radius` of a jump of more than `jump` (relative) in its depth
// (depth_discontinuities of view_geometry.hpp).
std::vector<cv::Mat1b> depth_edge_masks(const std::vector<DepthObservation>& views, double jump,
                                        int radius);

// L = (1/N) sum over Gaussians i and views v where i's centre projects onto an edge pixel of v
// (edges[v]) and lies on the near surface there (|z - D| <= tolerance D, D the smallest observed
// depth in the 3x3 pixels around) of sigma_iv = sqrt(sum_k exp(2 s_k) (a_k . d)^2), a_k the
// Gaussian's unit axes, s its log-scales and d the unit ray from v's camera centre to the mean.
// grad (resized to N x 3) receives dL/d(log_scales): exp(2 s_k) (a_k . d)^2 / (N sigma_iv)
// summed over the flagged views. Parallel over Gaussians, deterministic.
double depth_edge_extent_loss(const GaussianModel& model,
                              const std::vector<DepthObservation>& views,
                              const std::vector<cv::Mat1b>& edges, double tolerance,
                              std::vector<float>* grad = nullptr);

}  // namespace gslift
