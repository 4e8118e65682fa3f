#include "nodes/splat/projection.hpp"

#include <algorithm>
#include <cmath>

namespace gslift {

namespace {

constexpr float kDilation = 0.3f;  // low-pass filter added to the 2D covariance (3DGS)
constexpr float kFrustumSlack = 1.3f;

// Rotation matrix of the unit quaternion (w, x, y, z).
Eigen::Matrix3f rotation(const Eigen::Vector4f& q) {
  const float w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Matrix3f R;
  R << 1.f - 2.f * (y * y + z * z), 2.f * (x * y - w * z), 2.f * (x * z + w * y),
      2.f * (x * y + w * z), 1.f - 2.f * (x * x + z * z), 2.f * (y * z - w * x),
      2.f * (x * z - w * y), 2.f * (y * z + w * x), 1.f - 2.f * (x * x + y * y);
  return R;
}

// d L / d q for L depending on R(q) through dL/dR (q unit, before normalisation's chain rule).
Eigen::Vector4f rotation_backward(const Eigen::Vector4f& q, const Eigen::Matrix3f& dR) {
  const float w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Vector4f dq;
  dq[0] = 2.f * (-z * dR(0, 1) + y * dR(0, 2) + z * dR(1, 0) - x * dR(1, 2) - y * dR(2, 0) +
                 x * dR(2, 1));
  dq[1] = 2.f * (y * dR(0, 1) + z * dR(0, 2) + y * dR(1, 0) - 2.f * x * dR(1, 1) - w * dR(1, 2) +
                 z * dR(2, 0) + w * dR(2, 1) - 2.f * x * dR(2, 2));
  dq[2] = 2.f * (-2.f * y * dR(0, 0) + x * dR(0, 1) + w * dR(0, 2) + x * dR(1, 0) + z * dR(1, 2) -
                 w * dR(2, 0) + z * dR(2, 1) - 2.f * y * dR(2, 2));
  dq[3] = 2.f * (-2.f * z * dR(0, 0) - w * dR(0, 1) + x * dR(0, 2) + w * dR(1, 0) -
                 2.f * z * dR(1, 1) + y * dR(1, 2) + x * dR(2, 0) + y * dR(2, 1));
  return dq;
}

// Everything both passes derive from one Gaussian's parameters.
struct GaussianGeometry {
  Eigen::Vector3f mu, cam;  // world mean, camera-space mean
  Eigen::Vector4f q_unit;
  float q_norm = 0;  // 0 when the quaternion was degenerate (identity used)
  Eigen::Vector3f scale;
  Eigen::Matrix3f Rg, M, cov_cam;  // rotation, M = Rg S, camera-space covariance W M M^T W^T
  float u = 0, v = 0;              // clamped x/z, y/z
  bool clamped_x = false, clamped_y = false;
  Eigen::Matrix<float, 2, 3> J;
  int axis = 0;    // shortest scale axis
  float sign = 1;  // normal = sign * Rg.col(axis)
};

GaussianGeometry geometry(const ViewTransform& view, const float* mean, const float* log_scale,
                          const float* quat) {
  GaussianGeometry g;
  g.mu = Eigen::Vector3f(mean[0], mean[1], mean[2]);
  g.cam = view.R * g.mu + view.t;
  const Eigen::Vector4f q(quat[0], quat[1], quat[2], quat[3]);
  const float n2 = q.squaredNorm();
  if (n2 > 1e-24f && std::isfinite(n2)) {
    g.q_norm = std::sqrt(n2);
    g.q_unit = q / g.q_norm;
  } else {
    g.q_unit = Eigen::Vector4f(1.f, 0.f, 0.f, 0.f);
  }
  g.scale = Eigen::Vector3f(std::exp(log_scale[0]), std::exp(log_scale[1]), std::exp(log_scale[2]));
  g.Rg = rotation(g.q_unit);
  g.M = g.Rg * g.scale.asDiagonal();
  g.cov_cam = view.R * (g.M * g.M.transpose()) * view.R.transpose();
  const float z = g.cam.z();
  const float u_raw = g.cam.x() / z, v_raw = g.cam.y() / z;
  g.u = std::clamp(u_raw, -view.lim_x, view.lim_x);
  g.v = std::clamp(v_raw, -view.lim_y, view.lim_y);
  g.clamped_x = g.u != u_raw;
  g.clamped_y = g.v != v_raw;
  g.J << view.fx / z, 0.f, -view.fx * g.u / z, 0.f, view.fy / z, -view.fy * g.v / z;
  g.axis = 0;
  for (int k = 1; k < 3; ++k)
    if (g.scale[k] < g.scale[g.axis]) g.axis = k;
  g.sign = g.Rg.col(g.axis).dot(g.mu - view.centre) > 0.f ? -1.f : 1.f;
  return g;
}

}  // namespace

ViewTransform::ViewTransform(const Camera& camera, const Pose& pose)
    : R(pose.R.cast<float>()),
      t(pose.t.cast<float>()),
      centre(pose.centre().cast<float>()),
      fx(float(camera.fx)),
      fy(float(camera.fy)),
      cx(float(camera.cx)),
      cy(float(camera.cy)),
      width(camera.width),
      height(camera.height),
      lim_x(kFrustumSlack * 0.5f * float(camera.width / camera.fx)),
      lim_y(kFrustumSlack * 0.5f * float(camera.height / camera.fy)) {}

bool project_gaussian(const ViewTransform& view, const float* mean, const float* log_scale,
                      const float* quat, float near, ProjectedGaussian& out) {
  out.radius = 0;
  const Eigen::Vector3f cam = view.R * Eigen::Vector3f(mean[0], mean[1], mean[2]) + view.t;
  if (!(cam.z() >= near) || !cam.allFinite()) return false;
  const GaussianGeometry g = geometry(view, mean, log_scale, quat);
  if (!g.cov_cam.allFinite()) return false;
  Eigen::Matrix2f cov = g.J * g.cov_cam * g.J.transpose();
  cov(0, 0) += kDilation;
  cov(1, 1) += kDilation;
  const float a = cov(0, 0), b = 0.5f * (cov(0, 1) + cov(1, 0)), c = cov(1, 1);
  const float det = a * c - b * b;
  if (!(det > 0.f) || !std::isfinite(det)) return false;
  out.cov2d = Eigen::Vector3f(a, b, c);
  out.conic = Eigen::Vector3f(c / det, -b / det, a / det);
  const float mid = 0.5f * (a + c);
  const float lambda_max = mid + std::sqrt(std::max(0.1f, mid * mid - det));
  out.radius = int(std::ceil(3.f * std::sqrt(lambda_max)));
  const float z = g.cam.z();
  out.mean2d =
      Eigen::Vector2f(view.fx * g.cam.x() / z + view.cx, view.fy * g.cam.y() / z + view.cy);
  out.depth = z;
  out.normal = g.sign * g.Rg.col(g.axis);
  return true;
}

void project_gaussian_backward(const ViewTransform& view, const float* mean, const float* log_scale,
                               const float* quat, const ProjectionGrads& grads, float* d_mean,
                               float* d_log_scale, float* d_quat, float* d_pose) {
  const GaussianGeometry g = geometry(view, mean, log_scale, quat);
  Eigen::Matrix2f cov = g.J * g.cov_cam * g.J.transpose();
  cov(0, 0) += kDilation;
  cov(1, 1) += kDilation;
  const float a = cov(0, 0), b = 0.5f * (cov(0, 1) + cov(1, 0)), c = cov(1, 1);
  const float det = a * c - b * b;
  Eigen::Matrix2f Q;
  Q << c / det, -b / det, -b / det, a / det;

  // Conic = cov^-1: dL/dcov = -Q G Q with G the symmetric gradient of Q (B appears twice in Q).
  Eigen::Matrix2f G;
  G << grads.conic[0], 0.5f * grads.conic[1], 0.5f * grads.conic[1], grads.conic[2];
  const Eigen::Matrix2f d_cov = -Q * G * Q;
  // cov = J C J^T + 0.3 I.
  const Eigen::Matrix3f d_cov_cam = g.J.transpose() * d_cov * g.J;
  const Eigen::Matrix<float, 2, 3> d_J = 2.f * d_cov * g.J * g.cov_cam;
  // C = W (M M^T) W^T, M = Rg S.
  const Eigen::Matrix3f d_sigma = view.R.transpose() * d_cov_cam * view.R;
  const Eigen::Matrix3f d_M = 2.f * d_sigma * g.M;
  Eigen::Matrix3f d_Rg = d_M * g.scale.asDiagonal();
  d_Rg.col(g.axis) += g.sign * grads.normal;
  const Eigen::Matrix3f RtdM = g.Rg.transpose() * d_M;
  for (int k = 0; k < 3; ++k) d_log_scale[k] += RtdM(k, k) * g.scale[k];
  if (g.q_norm > 0.f) {
    // Chain through q_unit = q / |q|.
    const Eigen::Vector4f d_unit = rotation_backward(g.q_unit, d_Rg);
    const Eigen::Vector4f d_q = (d_unit - g.q_unit * g.q_unit.dot(d_unit)) / g.q_norm;
    for (int k = 0; k < 4; ++k) d_quat[k] += d_q[k];
  }

  // Camera-space mean: through the 2D mean, the Jacobian and the depth.
  const float x = g.cam.x(), y = g.cam.y(), z = g.cam.z();
  const float iz = 1.f / z, iz2 = iz * iz;
  Eigen::Vector3f d_cam(0.f, 0.f, grads.depth);
  d_cam.x() += grads.mean2d.x() * view.fx * iz;
  d_cam.y() += grads.mean2d.y() * view.fy * iz;
  d_cam.z() -= (grads.mean2d.x() * view.fx * x + grads.mean2d.y() * view.fy * y) * iz2;
  d_cam.z() -= (d_J(0, 0) * view.fx + d_J(1, 1) * view.fy) * iz2;
  // J02 = -fx u / z with u = x/z unless clamped (then u is a constant).
  if (g.clamped_x) {
    d_cam.z() += d_J(0, 2) * view.fx * g.u * iz2;
  } else {
    d_cam.x() -= d_J(0, 2) * view.fx * iz2;
    d_cam.z() += d_J(0, 2) * 2.f * view.fx * x * iz2 * iz;
  }
  if (g.clamped_y) {
    d_cam.z() += d_J(1, 2) * view.fy * g.v * iz2;
  } else {
    d_cam.y() -= d_J(1, 2) * view.fy * iz2;
    d_cam.z() += d_J(1, 2) * 2.f * view.fy * y * iz2 * iz;
  }
  const Eigen::Vector3f d_mu = view.R.transpose() * d_cam;
  for (int k = 0; k < 3; ++k) d_mean[k] += d_mu[k];
  if (d_pose) {
    // The view's pose moved by a small rotation w and translation dt in camera space:
    // cam' = (I + [w]x) cam + dt, C' = C + [w]x C - C [w]x. dL/dw from the mean is cam x d_cam;
    // from the covariance tr((C G - G C) [w]x) with G = dL/dC symmetric.
    const Eigen::Matrix3f A = g.cov_cam * d_cov_cam - d_cov_cam * g.cov_cam;
    const Eigen::Vector3f d_w =
        g.cam.cross(d_cam) +
        Eigen::Vector3f(A(1, 2) - A(2, 1), A(2, 0) - A(0, 2), A(0, 1) - A(1, 0));
    for (int k = 0; k < 3; ++k) {
      d_pose[k] += d_w[k];
      d_pose[3 + k] += d_cam[k];
    }
  }
}

}  // namespace gslift
