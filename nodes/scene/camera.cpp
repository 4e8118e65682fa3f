#include "nodes/scene/camera.hpp"

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
