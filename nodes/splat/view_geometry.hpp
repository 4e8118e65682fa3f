// How right a reconstruction's geometry is in one view, against that view's ground-truth depth:
// the held-out view is where every method here is judged, and where a few training views leave
// holes and floaters that training PSNR never shows.
#pragma once

#include <limits>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/caption_strip.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

// Per pixel of a forward pass (row-major), the median depth: the camera depth of the Gaussian
// at which the accumulated opacity front to back reaches 0.5, the surface the pixel's ray hits
// (2DGS and RaDe-GS evaluate geometry with it); 0 where it never does. The expected depth
// sum w_i z_i / alpha of a pixel on a silhouette lies between the object and what is behind
// it, so a band around every silhouette would read as floating in front of the background.
std::vector<float> median_depth(const GaussianModel& model, const Pose& pose,
                                const RenderOutput& forward);

struct ViewGeometry {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  // PSNR (dB) over every pixel, and over the covered pixels only.
  double psnr = kNone, psnr_covered = kNone;
  // Fraction of the view's surface pixels whose surface point some training view sees.
  double coverage = kNone;
  // Over surface pixels (ground-truth depth > 0), d = rendered median depth, d* = true:
  double depth_abs_rel_median = kNone;  // median |d - d*| / d* where the model draws (alpha >= 0.5)
  double depth_within_5pct = kNone;     // |d - d*| < 0.05 d* and drawn, over all surface pixels
  double floaters = kNone;              // drawn and d < 0.9 d* (more than 10% in front)
  double floaters_covered = kNone;      // floaters among the covered surface pixels
  // Floaters by the expected depth (sum w_i z_i / alpha) instead: silhouette bands included.
  double floaters_expected_depth = kNone;
  // The floaters split by where they lie (both over all surface pixels; they sum to `floaters`):
  // within kDiscontinuityRadius pixels of a ground-truth depth discontinuity, where a pixel mixes
  // two surfaces and its true depth is ambiguous (stereo benchmarks, e.g. Middlebury, score such
  // "disc" pixels apart), and away from every discontinuity.
  double floaters_at_discontinuity = kNone;
  double floaters_away_from_discontinuity = kNone;
  double holes = kNone;          // alpha < 0.5
  double holes_covered = kNone;  // alpha < 0.5 among the covered surface pixels
};

// Pixels within `radius` pixels (Chebyshev distance) of a depth discontinuity of `depth`: a pair
// of 4-neighbours whose depths differ by more than `jump` relative to the nearer one, or a
// surface pixel next to one without depth (0). 0 elsewhere, 1 there.
inline constexpr int kDiscontinuityRadius = 2;
cv::Mat1b depth_discontinuities(const cv::Mat1f& depth, double jump = 0.1,
                                int radius = kDiscontinuityRadius);

// Pixels of view `view` whose ground-truth surface point is seen by one of `train` views: it
// projects inside that view, in front of its camera, and its depth there agrees with that view's
// ground-truth depth within `tolerance` (relative), i.e. nothing occludes it. Pixels without a
// ground-truth depth are 0. Needs gt_depth on every view involved (throws InputError otherwise).
cv::Mat1b covered_pixels(const Capture& capture, int view, const std::vector<int>& train,
                         double tolerance = 0.01);

// Renders the model at `view` (RGB over `background`, depth, alpha) and scores it; throws
// InputError when the view has no ground-truth depth. With `picture`, also draws the render
// (8-bit RGB) with the floaters red, the holes on covered pixels blue and the uncovered surfaces
// greyed out, for a person to see where the geometry fails.
ViewGeometry view_geometry(const GaussianModel& model, const Capture& capture, int view,
                           const std::vector<int>& train,
                           const Eigen::Vector3f& background = Eigen::Vector3f::Zero(),
                           cv::Mat3b* picture = nullptr);

// What the colours of view_geometry's picture mean, for its caption
// (nodes/scene/caption_strip.hpp).
std::vector<LegendEntry> view_geometry_legend();

// The mean of each field over the given views (NaN fields are left out of their mean); with
// `pictures`, each view's picture (view_geometry) in the order of `views`.
ViewGeometry mean_view_geometry(const GaussianModel& model, const Capture& capture,
                                const std::vector<int>& views, const std::vector<int>& train,
                                const Eigen::Vector3f& background = Eigen::Vector3f::Zero(),
                                std::vector<cv::Mat3b>* pictures = nullptr);

}  // namespace gslift
