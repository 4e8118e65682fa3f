#include "nodes/ingest/opencv_camera.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace gslift {

cv::Mat opencv_camera_matrix(const Camera& c) {
  cv::Mat k;
  cv::eigen2cv(c.K(), k);
  k.at<double>(0, 2) -= 0.5;
  k.at<double>(1, 2) -= 0.5;
  return k;
}

std::vector<cv::Point2d> pixel_rays(const Camera& c, const std::vector<cv::Point2d>& pixels) {
  std::vector<cv::Point2d> rays(pixels.size());
  if (c.distortion.empty()) {
    for (size_t i = 0; i < pixels.size(); ++i)
      rays[i] = {(pixels[i].x - c.cx) / c.fx, (pixels[i].y - c.cy) / c.fy};
    return rays;
  }
  if (pixels.empty()) return rays;
  std::vector<cv::Point2d> opencv(pixels.size());
  for (size_t i = 0; i < pixels.size(); ++i) opencv[i] = pixels[i] - cv::Point2d(0.5, 0.5);
  cv::undistortPoints(
      opencv, rays, opencv_camera_matrix(c), c.distortion, cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  return rays;
}

std::vector<cv::Point2d> project_to_pixels(const Camera& c,
                                           const std::vector<cv::Point3d>& points) {
  std::vector<cv::Point2d> pixels(points.size());
  if (c.distortion.empty()) {
    for (size_t i = 0; i < points.size(); ++i)
      pixels[i] = {c.fx * points[i].x / points[i].z + c.cx,
                   c.fy * points[i].y / points[i].z + c.cy};
    return pixels;
  }
  if (points.empty()) return pixels;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), opencv_camera_matrix(c),
                    c.distortion, pixels);
  for (auto& p : pixels) p += cv::Point2d(0.5, 0.5);
  return pixels;
}

}  // namespace gslift
