#include "nodes/ingest/view_files.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "nodes/ingest/opencv_camera.hpp"
#include "nodes/scene/image_io.hpp"

namespace gslift {
namespace {

using Decode = std::function<cv::Mat(const std::filesystem::path&)>;

bool same_camera(const Camera& a, const Camera& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.distortion == b.distortion;
}

// Undistortion from a captured camera (with distortion) to an ideal pinhole `target`. Its maps
// cost about as much as decoding the image (24 ms for one of DTU's 1600x1200 photos) and take 4
// bytes per pixel twice (15 MB there): when several sources use them (the views of a capture
// with one camera, make_views; a view's RGB, depth and label maps) they are computed on the first
// load and kept for the later loads and threads; a single source computes them on each load and
// lets them go, so that a capture with a camera per photo (DTU's COLMAP model) does not hold a
// pair of maps per view (they were 384 of a 639 MB peak on DTU at 400x300).
class Undistorter {
 public:
  Undistorter(const Camera& captured, const Camera& target)
      : captured_(captured), target_(target) {}
  bool maps(const Camera& captured, const Camera& target) const {
    return same_camera(captured, captured_) && same_camera(target, target_);
  }
  // Counts a source that undistorts through this; called before any load.
  void add_user() { ++users_; }

  // The image the ideal pinhole would have seen.
  cv::Mat apply(const cv::Mat& m, int interpolation) {
    cv::Mat out;
    if (users_ < 2) {
      cv::Mat map_x, map_y;
      compute(map_x, map_y);
      cv::remap(m, out, map_x, map_y, interpolation, cv::BORDER_CONSTANT, cv::Scalar::all(0));
      return out;
    }
    std::call_once(once_, [&] { compute(map_x_, map_y_); });
    cv::remap(m, out, map_x_, map_y_, interpolation, cv::BORDER_CONSTANT, cv::Scalar::all(0));
    return out;
  }

 private:
  void compute(cv::Mat& map_x, cv::Mat& map_y) const {
    cv::initUndistortRectifyMap(opencv_camera_matrix(captured_), captured_.distortion,
                                cv::noArray(), opencv_camera_matrix(target_),
                                cv::Size(target_.width, target_.height), CV_32FC1, map_x, map_y);
  }

  Camera captured_, target_;
  int users_ = 0;
  std::once_flag once_;
  cv::Mat map_x_, map_y_;
};

// `camera` is the captured one; `target` the full-resolution pinhole it is undistorted into (the
// same camera when nothing is undistorted), by `undistorter` (null when nothing is undistorted).
ImageSource checked_source(const std::filesystem::path& path, const Camera& camera,
                           const Camera& target, int downscale,
                           std::shared_ptr<Undistorter> undistorter, Decode decode,
                           int interpolation) {
  if (path.empty()) return {};
  const Camera scaled = target.scaled(1.0 / downscale);
  if (undistorter) undistorter->add_user();
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

// A depth map of a sensor of its own, registered to the full-resolution `target` and resized to
// the view's resolution (nearest: averaging across a depth edge invents values).
ImageSource registered_depth_source(const ViewFiles& f, const Camera& target, int downscale) {
  const Camera scaled = target.scaled(1.0 / downscale);
  const DepthSensor sensor = *f.depth_sensor;
  const bool fits_file = f.depth_sensor_fits_file;
  const double scale = f.depth_scale;
  return ImageSource::on_disk(f.depth, [=](const std::filesystem::path& p) {
    const cv::Mat depth = read_depth(p, scale);
    DepthSensor s = sensor;
    const Camera& c = sensor.camera;
    if (fits_file && (depth.cols != c.width || depth.rows != c.height)) {
      // The same camera at the file's resolution: one scale for both axes.
      const double k = static_cast<double>(depth.cols) / c.width;
      s.camera = c.scaled(k);
      if (s.camera.width != depth.cols || s.camera.height != depth.rows)
        throw InputError(p.string() + ": depth map is " + std::to_string(depth.cols) + " x " +
                         std::to_string(depth.rows) + ", not the colour camera's " +
                         std::to_string(c.width) + " x " + std::to_string(c.height) +
                         " scaled by one factor");
    }
    if (depth.cols != s.camera.width || depth.rows != s.camera.height)
      throw InputError(p.string() + ": depth map is " + std::to_string(depth.cols) + " x " +
                       std::to_string(depth.rows) + ", but its depth camera is " +
                       std::to_string(s.camera.width) + " x " + std::to_string(s.camera.height));
    cv::Mat m = register_depth(depth, s, target);
    if (downscale == 1) return m;
    cv::Mat out;
    cv::resize(m, out, cv::Size(scaled.width, scaled.height), 0, 0, cv::INTER_NEAREST);
    return out;
  });
}

// Ground-truth label maps of the capture layout must be 16-bit (docs/capture_format.md).
cv::Mat read_gt_labels(const std::filesystem::path& p) {
  return read_label_map(p, false);
}

}  // namespace

cv::Rect undistorted_valid_rect(const Camera& c, int multiple) {
  const cv::Rect whole(0, 0, c.width, c.height);
  if (c.distortion.empty()) return whole;
  // The border of the captured image, every pixel edge of it, in gslift pixel coordinates.
  std::vector<cv::Point2d> border;
  const double x1 = c.width, y1 = c.height;
  for (int u = 0; u <= c.width; ++u)
    border.push_back({double(u), 0}), border.push_back({double(u), y1});
  for (int v = 0; v <= c.height; ++v)
    border.push_back({0, double(v)}), border.push_back({x1, double(v)});
  const std::vector<cv::Point2d> rays = pixel_rays(c, border);
  // The tightest bound of each side of the ideal image.
  double left = 0, right = c.width, top = 0, bottom = c.height;
  for (size_t i = 0; i < rays.size(); ++i) {
    const double x = c.fx * rays[i].x + c.cx, y = c.fy * rays[i].y + c.cy;
    const cv::Point2d& b = border[i];
    if (b.x == 0) left = std::max(left, x);
    if (b.x == x1) right = std::min(right, x);
    if (b.y == 0) top = std::max(top, y);
    if (b.y == y1) bottom = std::min(bottom, y);
  }
  // One more pixel on each side: bilinear interpolation reads the neighbours of a pixel mapped
  // just inside the border.
  const int l = static_cast<int>(std::ceil(left)) + 1, t = static_cast<int>(std::ceil(top)) + 1;
  int w = static_cast<int>(std::floor(right)) - 1 - l,
      h = static_cast<int>(std::floor(bottom)) - 1 - t;
  w -= w % std::max(multiple, 1);
  h -= h % std::max(multiple, 1);
  if (w <= 0 || h <= 0)
    throw InputError("camera " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                     ": its distortion leaves no valid rectangle to crop to");
  return cv::Rect(l, t, w, h) & whole;
}

namespace {

// View f read as make_views does, its images undistorted by the Undistorter in `shared` that maps
// its camera, added there when none does yet.
View make_view(const ViewFiles& f, const CaptureOptions& options,
               std::vector<std::shared_ptr<Undistorter>>& shared) {
  const Camera& c = f.camera;
  const int downscale = options.downscale;
  // The full-resolution pinhole the images are read into.
  Camera target = c;
  if (options.undistort && !c.distortion.empty()) {
    target.distortion.clear();
    if (options.undistort_crop) {
      const cv::Rect r = undistorted_valid_rect(c, downscale);
      target.width = r.width;
      target.height = r.height;
      target.cx -= r.x;
      target.cy -= r.y;
    }
  }
  View v;
  v.name = f.name;
  v.camera = downscale == 1 ? target : target.scaled(1.0 / downscale);
  v.pose = f.pose;
  v.held_out = f.held_out;
  std::shared_ptr<Undistorter> undistorter;
  if (!c.distortion.empty() && target.distortion.empty()) {
    const auto found = std::find_if(shared.begin(), shared.end(),
                                    [&](const auto& u) { return u->maps(c, target); });
    undistorter = found != shared.end()
                      ? *found
                      : shared.emplace_back(std::make_shared<Undistorter>(c, target));
  }
  auto source = [&](const std::filesystem::path& path, Decode decode, int interpolation) {
    return checked_source(path, c, target, downscale, undistorter, std::move(decode),
                          interpolation);
  };
  v.rgb = source(
      f.rgb, [](const auto& p) { return read_rgb(p); }, cv::INTER_AREA);
  const double scale = f.depth_scale;
  v.depth = f.depth_sensor && !f.depth.empty()
                ? registered_depth_source(f, target, downscale)
                : source(
                      f.depth, [scale](const auto& p) { return read_depth(p, scale); },
                      cv::INTER_NEAREST);
  v.gt_instance = source(f.gt_instance, read_gt_labels, cv::INTER_NEAREST);
  v.gt_semantic = source(f.gt_semantic, read_gt_labels, cv::INTER_NEAREST);
  v.gt_depth = source(f.gt_depth, read_float_tiff, cv::INTER_NEAREST);
  v.gt_normal = source(f.gt_normal, read_float_tiff, cv::INTER_NEAREST);
  return v;
}

}  // namespace

std::vector<View> make_views(const std::vector<ViewFiles>& files, const CaptureOptions& options) {
  std::vector<std::shared_ptr<Undistorter>> undistorters;
  std::vector<View> views;
  views.reserve(files.size());
  for (const ViewFiles& f : files) views.push_back(make_view(f, options, undistorters));
  return views;
}

}  // namespace gslift
