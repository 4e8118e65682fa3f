#include "nodes/splat/depth_normals.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

namespace gslift {

cv::Mat smooth_valid_depth(const cv::Mat& depth, double sigma) {
  // Normalised convolution: blur(depth * valid) / blur(valid), so holes (0) do not pull depths
  // towards zero; invalid pixels stay invalid. Pixels whose window is mostly across a depth edge
  // are not protected here: the relative-jump test in normals_from_depth rejects them.
  cv::Mat valid = cv::Mat::zeros(depth.size(), CV_32FC1), masked = depth.clone();
  for (int r = 0; r < depth.rows; ++r)
    for (int c = 0; c < depth.cols; ++c) {
      const float d = depth.at<float>(r, c);
      const bool ok = d > 0.f && std::isfinite(d);
      valid.at<float>(r, c) = ok ? 1.f : 0.f;
      if (!ok) masked.at<float>(r, c) = 0.f;
    }
  cv::Mat num, den;
  cv::GaussianBlur(masked, num, cv::Size(), sigma, sigma, cv::BORDER_CONSTANT);
  cv::GaussianBlur(valid, den, cv::Size(), sigma, sigma, cv::BORDER_CONSTANT);
  cv::Mat out = cv::Mat::zeros(depth.size(), CV_32FC1);
  for (int r = 0; r < depth.rows; ++r)
    for (int c = 0; c < depth.cols; ++c)
      if (valid.at<float>(r, c) > 0.f && den.at<float>(r, c) > 1e-6f)
        out.at<float>(r, c) = num.at<float>(r, c) / den.at<float>(r, c);
  return out;
}

cv::Mat normals_from_depth(const cv::Mat& raw_depth, const Camera& camera, const Pose& pose,
                           double max_relative_jump, int baseline, double smoothing) {
  if (raw_depth.type() != CV_32FC1)
    throw std::invalid_argument("normals_from_depth: need CV_32FC1");
  const cv::Mat depth = smoothing > 0 ? smooth_valid_depth(raw_depth, smoothing) : raw_depth;
  const int b = std::max(baseline, 1);
  cv::Mat normals = cv::Mat::zeros(depth.size(), CV_32FC3);
  auto point = [&](int u, int v) {
    const double d = depth.at<float>(v, u);
    return Eigen::Vector3d(d * (u + 0.5 - camera.cx) / camera.fx,
                           d * (v + 0.5 - camera.cy) / camera.fy, d);
  };
  auto usable = [&](float d, float centre) {
    return d > 0.f && std::isfinite(d) && std::abs(d - centre) <= max_relative_jump * centre;
  };
  for (int v = b; v + b < depth.rows; ++v) {
    for (int u = b; u + b < depth.cols; ++u) {
      const float d = depth.at<float>(v, u);
      if (!(d > 0.f) || !std::isfinite(d)) continue;
      if (!usable(depth.at<float>(v, u - b), d) || !usable(depth.at<float>(v, u + b), d) ||
          !usable(depth.at<float>(v - b, u), d) || !usable(depth.at<float>(v + b, u), d))
        continue;
      const Eigen::Vector3d du = point(u + b, v) - point(u - b, v);
      const Eigen::Vector3d dv = point(u, v + b) - point(u, v - b);
      Eigen::Vector3d n = du.cross(dv);
      const double len = n.norm();
      if (len <= 0) continue;
      n /= len;
      if (n.dot(point(u, v)) > 0) n = -n;
      const Eigen::Vector3d world = pose.R.transpose() * n;
      normals.at<cv::Vec3f>(v, u) = cv::Vec3f(world.x(), world.y(), world.z());
    }
  }
  return normals;
}

}  // namespace gslift
