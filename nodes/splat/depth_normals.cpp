#include "nodes/splat/depth_normals.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Core>

namespace gslift {

cv::Mat normals_from_depth(const cv::Mat& depth, const Camera& camera, const Pose& pose,
                           double max_relative_jump) {
  if (depth.type() != CV_32FC1) throw std::invalid_argument("normals_from_depth: need CV_32FC1");
  cv::Mat normals = cv::Mat::zeros(depth.size(), CV_32FC3);
  auto point = [&](int u, int v) {
    const double d = depth.at<float>(v, u);
    return Eigen::Vector3d(d * (u + 0.5 - camera.cx) / camera.fx,
                           d * (v + 0.5 - camera.cy) / camera.fy, d);
  };
  auto usable = [&](float d, float centre) {
    return d > 0.f && std::isfinite(d) && std::abs(d - centre) <= max_relative_jump * centre;
  };
  for (int v = 1; v + 1 < depth.rows; ++v) {
    for (int u = 1; u + 1 < depth.cols; ++u) {
      const float d = depth.at<float>(v, u);
      if (!(d > 0.f) || !std::isfinite(d)) continue;
      if (!usable(depth.at<float>(v, u - 1), d) || !usable(depth.at<float>(v, u + 1), d) ||
          !usable(depth.at<float>(v - 1, u), d) || !usable(depth.at<float>(v + 1, u), d))
        continue;
      const Eigen::Vector3d du = point(u + 1, v) - point(u - 1, v);
      const Eigen::Vector3d dv = point(u, v + 1) - point(u, v - 1);
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
