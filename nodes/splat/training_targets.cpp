#include "nodes/splat/training_targets.hpp"

#include <exception>
#include <string>

#include <tbb/parallel_for.h>

#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "nodes/splat/depth_normals.hpp"

namespace gslift {
namespace {

TargetImages make_images(const View& view, const Camera& camera, const cv::Mat& rgb,
                         const cv::Mat& depth, bool need_normals) {
  TargetImages t;
  t.camera = camera;
  t.rgb = rgb;
  t.ssim.emplace(t.rgb);
  t.depth = depth;
  if (!depth.empty() && need_normals)
    t.normals = normals_from_depth(depth, camera, view.pose, 0.1, 1, kPriorNormalSmoothing);
  return t;
}

TrainTarget make_target(const View& view, bool need_normals, bool need_half) {
  TrainTarget t;
  t.view = &view;
  cv::Mat rgb, depth;
  load_view_rgb(view).convertTo(rgb, CV_32FC3, 1.0 / 255);
  if (view.depth.present()) {
    depth = view.depth.load();
    if (depth.type() != CV_32FC1 || depth.size() != rgb.size())
      throw InputError("view '" + view.name + "': depth prior must be CV_32F of the image size");
  }
  t.full = make_images(view, view.camera, rgb, depth, need_normals);
  if (need_half) {
    const Camera half = view.camera.scaled(0.5);
    const cv::Size size(half.width, half.height);
    cv::Mat small_rgb, small_depth;
    cv::resize(rgb, small_rgb, size, 0, 0, cv::INTER_AREA);
    // Nearest, not area: averaging would blend invalid (0) pixels and depth edges into depths
    // that exist nowhere.
    if (!depth.empty()) cv::resize(depth, small_depth, size, 0, 0, cv::INTER_NEAREST);
    t.half = make_images(view, half, small_rgb, small_depth, need_normals);
  }
  return t;
}

}  // namespace

cv::Mat load_view_rgb(const View& view) {
  const cv::Mat rgb = view.rgb.load();
  if (rgb.type() != CV_8UC3 || rgb.cols != view.camera.width || rgb.rows != view.camera.height)
    throw InputError("view '" + view.name +
                     "': RGB image must be 8-bit 3-channel of the camera size " +
                     std::to_string(view.camera.width) + "x" + std::to_string(view.camera.height));
  return rgb;
}

std::vector<TrainTarget> make_targets(const Capture& capture, const std::vector<int>& views,
                                      bool need_normals, bool need_half) {
  // Decoding, undistorting and resizing the photos was half of a 100-step DTU run at 400x300
  // (prepare 2.5 of 4.9 s) on one core. An error is rethrown for the first failing view in
  // `views`, whatever the scheduling, so the message never depends on the thread count.
  std::vector<TrainTarget> targets(views.size());
  std::vector<std::exception_ptr> failed(views.size());
  tbb::parallel_for(size_t(0), views.size(), [&](size_t i) {
    try {
      targets[i] = make_target(capture.views[views[i]], need_normals, need_half);
    } catch (...) {
      failed[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
  return targets;
}

Eigen::Vector3f mean_colour(const std::vector<TrainTarget>& targets) {
  cv::Scalar sum;
  for (const TrainTarget& t : targets) sum += cv::mean(t.full.rgb);
  const double n = static_cast<double>(targets.size());
  return Eigen::Vector3f(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
}

}  // namespace gslift
