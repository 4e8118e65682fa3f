// Class-agnostic automatic masks from a depth map, written as SAM automatic masks, for captures
// with depth (RGB-D sensors, an MVS depth prior) where colour segmentation (masks.auto) gives no
// object-level grouping. Three geometric cues, each a classical one:
//  - dominant planes (floor, walls, large table tops): sequential RANSAC (Fischler, Bolles 1981)
//    on the back-projected points, an inlier near the plane AND with a normal along it; each
//    connected piece of a plane's inliers large enough is a segment of its own;
//  - depth discontinuities: neighbours whose depths differ by more than a fraction of the depth
//    are never joined (occluding contours, Hoiem et al. 2011);
//  - normal discontinuities (creases): where the surface normal turns by more than an angle
//    across a few pixels; a concave crease (the surfaces face each other, as where a box stands
//    on the floor or a person leans on a table) separates objects, a convex one (a box's own
//    edge) parts of one object (the local convexity of LCCP, Stein et al., CVPR 2014).
// Granularity 0 (groups, like SAM's whole masks) = the planes, and the connected pieces of the
// rest that no depth discontinuity separates; 1 (objects) cuts those at concave creases; 2 (parts)
// at every crease. Each granularity cuts the segments of the one before, so they nest: every part
// lies inside one object, every object inside one group. Quality on the embedded OR: docs/saga.md.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/masks/label_segments.hpp"
#include "nodes/scene/camera.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct GeometryMaskOptions {
  // Median filter aperture on the depth before anything else (1, 3 or 5): a depth prior's
  // per-pixel noise would otherwise cut surfaces into speckle.
  int median = 5;
  // Normals are the cross product of point differences across 2 * normal_step pixels of the
  // box-filtered points: longer baselines average the noise, shorter ones keep thin parts.
  int normal_step = 2;
  // Neighbours more than this fraction of their depth apart are a depth discontinuity.
  double depth_jump = 0.02;
  // A pixel whose normals normal_step to either side differ by more than this (degrees) lies on a
  // crease: objects (granularity 1) are cut at concave creases, parts (2) at every crease.
  double crease_angle = 30;
  // Dominant planes: at most max_planes, each of at least plane_min_fraction of the valid pixels
  // (one connected piece); inliers lie within plane_distance * depth of the plane (the depth
  // prior's noise grows with depth) and their normal within plane_angle degrees of its normal.
  int max_planes = 6;
  double plane_min_fraction = 0.05;
  double plane_distance = 0.03;
  double plane_angle = 20;
  int ransac_iterations = 300;
  SegmentKeep keep;  // min_area, max_area_fraction, views (label_segments.hpp)
};

const ParamTable<GeometryMaskOptions>& geometry_mask_param_table();

// Segment ids per pixel at each granularity (CV_32SC1, dense from 0; -1 = invalid depth), and the
// dominant planes (CV_32SC1, 0 = none, k = the k-th plane segment).
struct GeometrySegments {
  std::vector<cv::Mat1i> labels;  // [granularity]
  cv::Mat1i planes;
  int plane_count = 0;
};

// depth: CV_32FC1 metres, 0 = invalid, of the camera's size (pinhole). Deterministic. Throws
// InputError (naming `where`) when depth is empty, not CV_32FC1 or not of the camera's size.
GeometrySegments geometry_segments(const cv::Mat& depth, const Camera& camera,
                                   const GeometryMaskOptions& options,
                                   const std::string& where = "masks.geometry");

// The masks of one depth map: each segment of at least min_area pixels and at most
// max_area_fraction of the view, with its granularity and score 1. No valid depth: no masks.
std::vector<Mask> geometry_masks(const cv::Mat& depth, const Camera& camera,
                                 const GeometryMaskOptions& options,
                                 const std::string& where = "masks.geometry");

// geometry_masks of every view of options.views, in capture order (parallel over views); a depth
// map of another size than its view is resized to it (nearest). Throws InputError naming the view
// when a view has no depth prior, and when no view has a mask; views whose depth gives no mask
// are named in a warning and keep no masks.
MaskSet geometry_mask_set(const Capture& capture, const GeometryMaskOptions& options);

}  // namespace gslift
