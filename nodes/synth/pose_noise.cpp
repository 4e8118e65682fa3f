#include "nodes/synth/pose_noise.hpp"

#include <cmath>

namespace gslift::synth {

Pose perturb_pose(const Pose& pose, double rotation_deg, double translation_m, RandomStream& rng) {
  if (rotation_deg <= 0 && translation_m <= 0) return pose;
  Eigen::Vector3d axis(rng.normal(), rng.normal(), rng.normal());
  if (axis.norm() < 1e-12) axis = Eigen::Vector3d::UnitZ();
  const double angle = rng.normal(0, rotation_deg) * M_PI / 180.0;
  const Eigen::Vector3d centre =
      pose.centre() + Eigen::Vector3d(rng.normal(0, translation_m), rng.normal(0, translation_m),
                                      rng.normal(0, translation_m));
  Pose out;
  out.R = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix() * pose.R;
  out.t = -out.R * centre;
  return out;
}

}  // namespace gslift::synth
