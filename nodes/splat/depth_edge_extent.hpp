// Silhouette overhang along the training rays (issue 11): a Gaussian of an object that sits at a
// depth discontinuity of some training view's depth prior, on its near side, is seen by that
// view at the object's silhouette. Its extent along that view's ray (the standard deviation
// sqrt(d^T Sigma d) along the unit ray d) is invisible to the view: edge-on, a disc may stretch
// towards or away from the camera for free. From another camera that stretch is a rim past the
// object, over space the object hides from every training view (80-84% of the held-out floater
// pixels, bench/splat_recon/README.md). This term charges those Gaussians for that extent; only
// their scales pay (means and rotations keep their photometric gradients).
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/free_space.hpp"

namespace gslift {

// What the loss reads of one view at a pixel: the smallest valid prior depth in the 3x3 pixels
// around it where the pixel lies within `radius` of a jump of more than `jump` (relative) in the
// view's depth (depth_discontinuities of view_geometry.hpp), 0 elsewhere. The loss tests every
// Gaussian against every view at a pixel in no order the cache can follow, so the view is kept
// small: a bit per pixel, set where that depth is > 0 (170 KB for four 640x532 views, where a
// byte mask and the 3x3 reads after it took 62% of the loss's cycles in cache misses), and the
// depths of the set pixels alone, in pixel order, found by the bits' rank (a full-size depth
// image per view had a third of the loss's samples at its read; the loss 7% faster without it,
// in the main job; perf, Zen 5).
class DepthEdgeView {
 public:
  // From the per-pixel depths (0 off the edges).
  explicit DepthEdgeView(const cv::Mat1f& nearest);
  // The depth at pixel (x, y) inside the view: 0 off the edges.
  float nearest(int x, int y) const {
    const size_t i = size_t(y) * size_t(cols_) + size_t(x);
    const uint64_t word = bits_[i >> 6], below = (uint64_t{1} << (i & 63)) - 1;
    if (!((word >> (i & 63)) & 1u)) return 0.f;
    return depths_[before_[i >> 6] + uint32_t(__builtin_popcountll(word & below))];
  }
  size_t size() const { return depths_.size(); }  // the edge pixels

 private:
  int cols_;
  std::vector<uint64_t> bits_;    // pixel y * cols + x
  std::vector<uint32_t> before_;  // per word of bits_, the set bits of the words before it
  std::vector<float> depths_;
};
std::vector<DepthEdgeView> depth_edges(const std::vector<DepthObservation>& views, double jump,
                                       int radius);

// L = (1/N) sum over Gaussians i and views v where i's centre projects onto an edge pixel of v
// (edges[v]) and lies on the near surface there (|z - D| <= tolerance D, D the edge's nearest
// depth) of sigma_iv = sqrt(sum_k exp(2 s_k) (a_k . d)^2), a_k the
// Gaussian's unit axes, s its log-scales and d the unit ray from v's camera centre to the mean.
// grad (resized to N x 3) receives dL/d(log_scales): exp(2 s_k) (a_k . d)^2 / (N sigma_iv)
// summed over the flagged views. Parallel over Gaussians, deterministic.
double depth_edge_extent_loss(const GaussianModel& model,
                              const std::vector<DepthObservation>& views,
                              const std::vector<DepthEdgeView>& edges, double tolerance,
                              std::vector<float>* grad = nullptr);

}  // namespace gslift
