#include "nodes/scene/camera.hpp"

#include <cmath>

#include "base/errors.hpp"

namespace gslift {

Eigen::Matrix3d Camera::K() const {
  Eigen::Matrix3d k;
  k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return k;
}

Camera Camera::scaled(double s) const {
  Camera c = *this;
  c.width = static_cast<int>(width * s + 0.5);
  c.height = static_cast<int>(height * s + 0.5);
  c.fx *= s;
  c.fy *= s;
  c.cx *= s;
  c.cy *= s;
  return c;
}

void check_image_size(long long width, long long height, const std::string& where) {
  if (width <= 0 || height <= 0)
    throw InputError(where + ": image size must be positive, got " + std::to_string(width) + " x " +
                     std::to_string(height));
  if (width > kMaxImagePixels || height > kMaxImagePixels / width)
    throw InputError(where + ": image size " + std::to_string(width) + " x " +
                     std::to_string(height) + " is over gslift's limit of " +
                     std::to_string(kMaxImagePixels) + " pixels (docs/security.md)");
}

void check_camera(const Camera& c, const std::string& where) {
  check_image_size(c.width, c.height, where);
  if (!(std::isfinite(c.fx) && std::isfinite(c.fy) && c.fx > 0 && c.fy > 0))
    throw InputError(where + ": focal lengths must be finite and positive, got fx " +
                     std::to_string(c.fx) + ", fy " + std::to_string(c.fy));
  if (!(std::isfinite(c.cx) && std::isfinite(c.cy)))
    throw InputError(where + ": the principal point must be finite");
  const size_t n = c.distortion.size();
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12)
    throw InputError(where + ": " + std::to_string(n) +
                     " distortion coefficients; OpenCV's models take 4, 5, 8 or 12");
  for (double d : c.distortion)
    if (!std::isfinite(d)) throw InputError(where + ": distortion coefficients must be finite");
}

Pose Pose::from_camera_to_world(const Eigen::Matrix4d& c2w) {
  Pose p;
  p.R = c2w.block<3, 3>(0, 0).transpose();
  p.t = -p.R * c2w.block<3, 1>(0, 3);
  return p;
}

Eigen::Matrix4d Pose::world_to_camera() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 3>(0, 0) = R;
  m.block<3, 1>(0, 3) = t;
  return m;
}

}  // namespace gslift
