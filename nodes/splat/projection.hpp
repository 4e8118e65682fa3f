// EWA projection of one 3D Gaussian into a pinhole view (EWA, Zwicker et al. 2002, as used
// by 3DGS) and its exact backward pass. Plain functions over one Gaussian's stored parameters so
// the rasterizer can run them in parallel and the tests can check them against hand-computed cases.
#pragma once

#include <Eigen/Core>

#include "nodes/scene/camera.hpp"

namespace gslift {

// A view in float precision, with the frustum limits of the projection Jacobian.
struct ViewTransform {
  Eigen::Matrix3f R;       // world -> camera rotation
  Eigen::Vector3f t;       // world -> camera translation
  Eigen::Vector3f centre;  // camera centre in world coordinates
  float fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;
  // x/z and y/z are clamped to +-1.3 tan(fov/2) in the Jacobian (3DGS): Gaussians far outside the
  // frustum would otherwise get huge, badly conditioned footprints.
  float lim_x = 0, lim_y = 0;

  ViewTransform(const Camera& camera, const Pose& pose);
};

// One Gaussian seen by one view.
struct ProjectedGaussian {
  Eigen::Vector2f mean2d;  // pixels, pixel (u,v) centre at (u+0.5, v+0.5)
  Eigen::Vector3f cov2d;   // (a, b, c) of [[a b][b c]], including the 0.3 px^2 dilation
  Eigen::Vector3f conic;   // (A, B, C): inverse of cov2d, alpha uses exp(-0.5 d^T [[A B][B C]] d)
  float depth = 0;         // camera-space z
  int radius = 0;          // ceil(3 sqrt(lambda_max(cov2d))) pixels; 0 = culled
  // Shortest scale axis in world space, sign chosen so that it faces the camera.
  Eigen::Vector3f normal;
};

// Projects the Gaussian (mean: 3 floats, log_scale: 3, quat: 4 as w x y z, unnormalised).
// Returns false when culled: behind the near plane, non-finite input, or a degenerate footprint.
// A zero quaternion is treated as the identity rotation (its gradient is then zero).
bool project_gaussian(const ViewTransform& view, const float* mean, const float* log_scale,
                      const float* quat, float near, ProjectedGaussian& out);

// dL/d outputs of project_gaussian.
struct ProjectionGrads {
  Eigen::Vector2f mean2d = Eigen::Vector2f::Zero();
  Eigen::Vector3f conic = Eigen::Vector3f::Zero();  // dL/dA, dL/dB, dL/dC (B counted once)
  float depth = 0;
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
};

// Adds dL/d(mean), dL/d(log_scale), dL/d(quat) for a Gaussian that project_gaussian accepted,
// and with d_pose (6 floats) dL/d of the view's pose correction through this Gaussian's
// projection: a rotation w then a translation dt applied in camera space (pose_correction.hpp).
void project_gaussian_backward(const ViewTransform& view, const float* mean, const float* log_scale,
                               const float* quat, const ProjectionGrads& grads, float* d_mean,
                               float* d_log_scale, float* d_quat, float* d_pose = nullptr);

}  // namespace gslift
