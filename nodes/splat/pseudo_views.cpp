#include "nodes/splat/pseudo_views.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"

namespace gslift {

Pose interpolate_pose(const Pose& a, const Pose& b, double t) {
  const Eigen::Quaterniond qa(a.R), qb(b.R);
  Pose p;
  p.R = qa.slerp(t, qb).normalized().toRotationMatrix();
  const Eigen::Vector3d centre = (1 - t) * a.centre() + t * b.centre();
  p.t = -p.R * centre;
  return p;
}

PseudoView warp_into_view(const Camera& camera, const Pose& pose,
                          const std::vector<WarpSource>& sources) {
  const int W = camera.width, H = camera.height;
  cv::Mat1f zbuf(H, W, std::numeric_limits<float>::infinity());
  cv::Mat3f colour(H, W, cv::Vec3f(0, 0, 0));
  for (const WarpSource& s : sources) {
    const Camera& c = *s.camera;
    if (s.rgb.type() != CV_32FC3 || s.depth.type() != CV_32FC1 || s.rgb.cols != c.width ||
        s.rgb.rows != c.height || s.depth.size() != s.rgb.size())
      throw InputError(
          "pseudo-view warp: a source's RGB (CV_32FC3) and depth (CV_32FC1) must "
          "have its camera's size " +
          std::to_string(c.width) + "x" + std::to_string(c.height));
    // Source camera -> target camera: x_t = R x_s + t.
    const Eigen::Matrix3d R = pose.R * s.pose->R.transpose();
    const Eigen::Vector3d t = pose.t - R * s.pose->t;
    for (int y = 0; y < c.height; ++y) {
      const float* d = s.depth.ptr<float>(y);
      const cv::Vec3f* rgb = s.rgb.ptr<cv::Vec3f>(y);
      for (int x = 0; x < c.width; ++x) {
        if (!(d[x] > 0) || !std::isfinite(d[x])) continue;
        const Eigen::Vector3d ps((x + 0.5 - c.cx) / c.fx * d[x], (y + 0.5 - c.cy) / c.fy * d[x],
                                 d[x]);
        const Eigen::Vector3d pt = R * ps + t;
        if (!(pt.z() > 0)) continue;
        const double u = camera.fx * pt.x() / pt.z() + camera.cx;
        const double v = camera.fy * pt.y() / pt.z() + camera.cy;
        if (!(u >= 0 && v >= 0 && u < W && v < H)) continue;
        const int iu = static_cast<int>(u), iv = static_cast<int>(v);
        const float z = static_cast<float>(pt.z());
        if (z < zbuf(iv, iu)) {
          zbuf(iv, iu) = z;
          colour(iv, iu) = rgb[x];
        }
      }
    }
  }
  PseudoView out;
  out.camera = camera;
  out.pose = pose;
  out.rgb = cv::Mat(H, W, CV_32FC3, cv::Scalar::all(0));
  out.depth = cv::Mat(H, W, CV_32FC1, cv::Scalar(0));
  out.valid = cv::Mat1b(H, W, uchar(0));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float z = zbuf(y, x);
      if (!std::isfinite(z)) continue;
      float nearest = z;
      for (int yy = std::max(y - 2, 0); yy <= std::min(y + 2, H - 1); ++yy)
        for (int xx = std::max(x - 2, 0); xx <= std::min(x + 2, W - 1); ++xx)
          nearest = std::min(nearest, zbuf(yy, xx));
      if (z > 1.05f * nearest) continue;
      out.valid(y, x) = 1;
      out.depth.at<float>(y, x) = z;
      out.rgb.at<cv::Vec3f>(y, x) = colour(y, x);
    }
  return out;
}

std::vector<PseudoView> pseudo_views_between(const std::vector<WarpSource>& sources,
                                             double max_axis_angle_deg, double scale) {
  std::vector<std::pair<size_t, size_t>> pairs;
  const double cos_max = std::cos(max_axis_angle_deg * M_PI / 180);
  for (size_t i = 0; i < sources.size(); ++i)
    for (size_t j = i + 1; j < sources.size(); ++j) {
      // Optical axes in world coordinates: the third row of each world-to-camera rotation.
      const Eigen::Vector3d ai = sources[i].pose->R.row(2), aj = sources[j].pose->R.row(2);
      if (ai.dot(aj) > cos_max) pairs.emplace_back(i, j);
    }
  std::vector<PseudoView> views(pairs.size());
  tbb::parallel_for(size_t(0), pairs.size(), [&](size_t k) {
    const auto [i, j] = pairs[k];
    views[k] = warp_into_view(sources[i].camera->scaled(scale),
                              interpolate_pose(*sources[i].pose, *sources[j].pose, 0.5), sources);
  });
  return views;
}

}  // namespace gslift
