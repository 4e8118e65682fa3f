#include "nodes/ingest/view_files.hpp"

#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "nodes/scene/image_io.hpp"

namespace gslift {
namespace {

using Decode = std::function<cv::Mat(const std::filesystem::path&)>;

// Undistortion maps of one camera, computed on the first load and shared by later loads (and
// threads): they cost about as much as decoding the image.
class Undistorter {
 public:
  explicit Undistorter(const Camera& camera) : camera_(camera) {}

  // The image an ideal pinhole with the same K would have seen.
  cv::Mat apply(const cv::Mat& m, int interpolation) {
    std::call_once(once_, [&] {
      cv::Mat k;
      cv::eigen2cv(camera_.K(), k);
      // OpenCV puts pixel centres at integer coordinates, gslift at +0.5 (camera.hpp).
      k.at<double>(0, 2) -= 0.5;
      k.at<double>(1, 2) -= 0.5;
      cv::initUndistortRectifyMap(k, camera_.distortion, cv::noArray(), k,
                                  cv::Size(camera_.width, camera_.height), CV_32FC1, map_x_,
                                  map_y_);
    });
    cv::Mat out;
    cv::remap(m, out, map_x_, map_y_, interpolation, cv::BORDER_CONSTANT, cv::Scalar::all(0));
    return out;
  }

 private:
  Camera camera_;
  std::once_flag once_;
  cv::Mat map_x_, map_y_;
};

ImageSource checked_source(const std::filesystem::path& path, const Camera& camera, int downscale,
                           bool undistort, Decode decode, int interpolation) {
  if (path.empty()) return {};
  const Camera scaled = camera.scaled(1.0 / downscale);
  std::shared_ptr<Undistorter> undistorter;
  if (undistort && !camera.distortion.empty()) undistorter = std::make_shared<Undistorter>(camera);
  return ImageSource::on_disk(path, [=](const std::filesystem::path& p) {
    cv::Mat m = decode(p);
    if (m.cols != camera.width || m.rows != camera.height)
      throw InputError(p.string() + ": image is " + std::to_string(m.cols) + " x " +
                       std::to_string(m.rows) + ", but its camera is " +
                       std::to_string(camera.width) + " x " + std::to_string(camera.height));
    if (undistorter)
      m = undistorter->apply(m, interpolation == cv::INTER_AREA ? cv::INTER_LINEAR : interpolation);
    if (downscale == 1) return m;
    cv::Mat out;
    cv::resize(m, out, cv::Size(scaled.width, scaled.height), 0, 0, interpolation);
    return out;
  });
}

// Ground-truth label maps of the capture layout must be 16-bit (docs/capture_format.md).
cv::Mat read_gt_labels(const std::filesystem::path& p) {
  return read_label_map(p, false);
}

}  // namespace

View make_view(const ViewFiles& f, int downscale, bool undistort) {
  const Camera& c = f.camera;
  View v;
  v.name = f.name;
  v.camera = downscale == 1 ? c : c.scaled(1.0 / downscale);
  if (undistort) v.camera.distortion.clear();
  v.pose = f.pose;
  v.held_out = f.held_out;
  v.rgb = checked_source(
      f.rgb, c, downscale, undistort, [](const auto& p) { return read_rgb(p); }, cv::INTER_AREA);
  const double scale = f.depth_scale;
  v.depth = checked_source(
      f.depth, c, downscale, undistort, [scale](const auto& p) { return read_depth(p, scale); },
      cv::INTER_NEAREST);
  v.gt_instance =
      checked_source(f.gt_instance, c, downscale, undistort, read_gt_labels, cv::INTER_NEAREST);
  v.gt_semantic =
      checked_source(f.gt_semantic, c, downscale, undistort, read_gt_labels, cv::INTER_NEAREST);
  v.gt_depth =
      checked_source(f.gt_depth, c, downscale, undistort, read_float_tiff, cv::INTER_NEAREST);
  v.gt_normal =
      checked_source(f.gt_normal, c, downscale, undistort, read_float_tiff, cv::INTER_NEAREST);
  return v;
}

}  // namespace gslift
