// The training views' targets, decoded once per reconstruction: float RGB with its SSIM
// statistics, the depth prior and the normals derived from it, at full and, for coarse-to-fine,
// half resolution.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nodes/scene/capture.hpp"
#include "nodes/splat/ssim.hpp"

namespace gslift {

// A training view's targets at one resolution.
struct TargetImages {
  Camera camera;                   // the view's camera at this resolution
  cv::Mat rgb;                     // CV_32FC3 [0,1]
  std::optional<SsimTarget> ssim;  // rgb's windowed statistics
  cv::Mat depth;                   // CV_32FC1 metres, empty without a prior
  cv::Mat normals;                 // CV_32FC3 world-space, empty without a prior or unasked
};

// What one training view contributes: full-resolution targets and, for coarse-to-fine, a copy at
// half resolution (empty camera when unused).
struct TrainTarget {
  const View* view = nullptr;
  TargetImages full, half;
};

// The view's RGB image; throws InputError unless it is 8-bit 3-channel of the camera's size.
cv::Mat load_view_rgb(const View& view);

// The targets of capture.views[v] for each v of `views`, in that order; normals from the depth
// prior when `need_normals`, the half-resolution copy when `need_half`. Decoded in parallel over
// the views (the same targets at any thread count). Throws the InputError of the first view in
// `views` whose images cannot be read, whose RGB image is not as load_view_rgb wants it, or whose
// depth prior is not CV_32F of the image size.
std::vector<TrainTarget> make_targets(const Capture& capture, const std::vector<int>& views,
                                      bool need_normals, bool need_half);

// The mean colour of the training images (full resolution).
Eigen::Vector3f mean_colour(const std::vector<TrainTarget>& targets);

}  // namespace gslift
