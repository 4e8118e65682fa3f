#include "nodes/splat/ray_depth.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace gslift {

RayDepths::RayDepths(const GaussianModel& model, const Camera& camera, const Pose& pose,
                     const std::vector<ProjectedGaussian>& projections)
    : coeffs_(model.size() * kCoeffs, 0.f),
      ray_x_(size_t((camera.width + kTileSize - 1) / kTileSize * kTileSize)),
      ray_y_(size_t((camera.height + kTileSize - 1) / kTileSize * kTileSize)),
      nearest_(model.size(), 0.f),
      sorted_bound_(model.size(), 0.f) {
  const float fx = static_cast<float>(camera.fx), fy = static_cast<float>(camera.fy);
  const float cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
  for (size_t x = 0; x < ray_x_.size(); ++x) ray_x_[x] = (float(x) + 0.5f - cx) / fx;
  for (size_t y = 0; y < ray_y_.size(); ++y) ray_y_[y] = (float(y) + 0.5f - cy) / fy;
  tbb::parallel_for(size_t(0), model.size(), [&](size_t i) {
    sorted_bound_[i] = (1 - kMaxRelative) * projections[i].depth;
    if (projections[i].radius == 0) return;
    const Eigen::Matrix3d R = pose.R * model.rotation(i);
    Eigen::Vector3d inv_var;
    double largest = 0;
    for (int k = 0; k < 3; ++k) {
      const double s = std::exp(static_cast<double>(model.log_scales[i * 3 + k]));
      inv_var[k] = 1 / (s * s);
      largest = std::max(largest, s);
    }
    const Eigen::Matrix3d P = R * inv_var.asDiagonal() * R.transpose();
    const Eigen::Vector3d m = pose.to_camera(
        Eigen::Vector3d(model.means[i * 3], model.means[i * 3 + 1], model.means[i * 3 + 2]));
    const Eigen::Vector3d a = P * m;
    const double reach = std::min(3 * largest, kMaxRelative * m[2]);
    const double c[kCoeffs] = {a[0],        a[1],         a[2],        P(0, 0),
                               2 * P(0, 1), P(1, 1),      2 * P(0, 2), 2 * P(1, 2),
                               P(2, 2),     m[2] - reach, m[2] + reach};
    for (int k = 0; k < kCoeffs; ++k) coeffs_[i * kCoeffs + k] = static_cast<float>(c[k]);
    nearest_[i] = coeffs_[i * kCoeffs + 9];
  });
}

}  // namespace gslift
