// A 3D Gaussian Splatting scene with extra per-Gaussian feature channels. Structure of arrays,
// float32, contiguous: the rasterizer and the optimiser index these directly, and Eigen::Map wraps
// them without copies. Values are stored pre-activation as in the INRIA PLY layout: log-scales,
// opacity logits, unnormalised quaternions (w, x, y, z).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "base/port_type.hpp"

namespace gslift {

struct GaussianModel {
  int sh_degree = 0;    // 0..3
  int feature_dim = 0;  // D extra channels (instance features, class scores), may be 0

  std::vector<float> means;           // N x 3
  std::vector<float> log_scales;      // N x 3
  std::vector<float> quats;           // N x 4, w first
  std::vector<float> opacity_logits;  // N
  std::vector<float> sh;              // N x K x 3, K = (sh_degree+1)^2, [gaussian][coef][rgb]
  std::vector<float> features;        // N x feature_dim

  // Segmentation results, empty or of size N; -1 = unassigned.
  std::vector<int32_t> instance_ids;
  std::vector<int32_t> class_ids;

  size_t size() const { return opacity_logits.size(); }
  static int sh_coeffs(int degree) { return (degree + 1) * (degree + 1); }
  // Gaussian i's rotation (its normalised quaternion; a zero quaternion is the identity): the
  // columns are its scale axes in world space.
  Eigen::Matrix3d rotation(size_t i) const;
  // Resizes every per-Gaussian array to n (new entries zero, quaternions identity).
  void resize(size_t n);
  // The Gaussians `indices` (in that order) as a model of their own, every array kept.
  GaussianModel subset(const std::vector<size_t>& indices) const;
  // A copy with `features` (size() x dim, row-major) as its feature channels: what every
  // frozen-geometry feature trainer returns (the geometry is the input's).
  GaussianModel with_features(std::vector<float> features, int dim) const {
    GaussianModel m = *this;
    m.feature_dim = dim;
    m.features = std::move(features);
    return m;
  }
};

GSLIFT_PORT_TYPE(GaussianModel, "GaussianModel");

}  // namespace gslift
