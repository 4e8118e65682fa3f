// Depth-warped pseudo-views (issue 11's second lever; the sparse-view 3DGS literature's standard
// tool): virtual cameras between the training cameras, with the training images forward-warped
// into them through their depth priors as pseudo ground truth. A model that fits four views can
// still hold floaters and needles that only a camera between them sees; supervising those in-
// between cameras, at a low weight and only where the warp is valid, penalises them.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"

namespace gslift {

// A training view as a warp source (borrowed): RGB CV_32FC3 [0,1], depth CV_32FC1 metres (0 or
// non-finite = none), both of the camera's size.
struct WarpSource {
  const Camera* camera = nullptr;
  const Pose* pose = nullptr;
  cv::Mat rgb;
  cv::Mat depth;
};

struct PseudoView {
  Camera camera;
  Pose pose;
  cv::Mat rgb;    // CV_32FC3, 0 where invalid
  cv::Mat depth;  // CV_32FC1 metres, 0 where invalid
  cv::Mat1b valid;
};

// The pose a fraction t of the way from a to b: camera centres interpolated linearly, rotations
// by slerp.
Pose interpolate_pose(const Pose& a, const Pose& b, double t);

// The sources forward-warped into (camera, pose): every source pixel with a depth is lifted to 3D
// and projected to the nearest target pixel, and each target pixel keeps the nearest point (z-
// buffer; ties go to the earlier source, then the earlier pixel: deterministic). A kept pixel is
// then invalidated when its depth exceeds 1.05 x the smallest depth in its 5x5 neighbourhood: a
// far surface seen through a gap between the splatted points of a near one, which the near one
// occludes. Throws InputError when a source's images do not match its camera.
PseudoView warp_into_view(const Camera& camera, const Pose& pose,
                          const std::vector<WarpSource>& sources);

// Pseudo-views halfway between each pair of sources whose optical axes are less than
// max_axis_angle_deg apart (cameras facing away from each other have no in-between view of the
// same scene), each with the first camera of its pair scaled by `scale` (e.g. 0.5: a quarter of
// the pixels; the lever regularises coarse geometry), warped from all sources. Pairs in index
// order; parallel over pairs.
std::vector<PseudoView> pseudo_views_between(const std::vector<WarpSource>& sources,
                                             double max_axis_angle_deg, double scale);

}  // namespace gslift
