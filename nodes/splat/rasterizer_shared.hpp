// What the rasterizer's forward pass (rasterizer_forward.cpp) and backward pass
// (rasterizer_backward.cpp) share: the model check, the activations, the SH colour of a Gaussian
// and the gathering of a tile's per-Gaussian values. Internal to nodes/splat.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "base/errors.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/projection.hpp"
#include "nodes/splat/raster_state.hpp"

namespace gslift {

inline void check_size(const char* what, size_t got, size_t expected) {
  if (got != expected)
    throw InputError(std::string("GaussianModel: ") + what + " has " + std::to_string(got) +
                     " values, expected " + std::to_string(expected));
}

inline void check_model(const GaussianModel& model) {
  if (model.sh_degree < 0 || model.sh_degree > 3)
    throw InputError("GaussianModel: sh_degree " + std::to_string(model.sh_degree) +
                     " is outside 0..3");
  if (model.feature_dim < 0) throw InputError("GaussianModel: negative feature_dim");
  const size_t n = model.size();
  check_size("means", model.means.size(), 3 * n);
  check_size("log_scales", model.log_scales.size(), 3 * n);
  check_size("quats", model.quats.size(), 4 * n);
  check_size("sh", model.sh.size(), n * GaussianModel::sh_coeffs(model.sh_degree) * 3);
  check_size("features", model.features.size(), n * model.feature_dim);
  if (n >= std::numeric_limits<uint32_t>::max())
    throw InputError("GaussianModel: too many Gaussians");
}

inline float sigmoid(float x) {
  return 1.f / (1.f + std::exp(-x));
}

// View direction of a Gaussian (camera centre -> mean) and its length.
inline Eigen::Vector3f view_direction(const ViewTransform& view, const float* mean, float& length) {
  const Eigen::Vector3f d = Eigen::Vector3f(mean[0], mean[1], mean[2]) - view.centre;
  length = std::max(d.norm(), 1e-12f);
  return d / length;
}

// SH colour before the clamp at 0: sum_k Y_k(dir) sh_k + 0.5 (3DGS).
inline Eigen::Vector3f sh_colour(const float* sh, int degree, const float* basis) {
  Eigen::Vector3f c = Eigen::Vector3f::Constant(0.5f);
  for (int k = 0; k < GaussianModel::sh_coeffs(degree); ++k)
    c += basis[k] * Eigen::Vector3f(sh[3 * k], sh[3 * k + 1], sh[3 * k + 2]);
  return c;
}

// Copies a tile's per-Gaussian values into a contiguous buffer (cache-friendly blending).
inline void gather_values(const RasterState& s, const TileGaussian* list, uint32_t count,
                          std::vector<float>& out) {
  out.resize(size_t(count) * s.channels);
  // A weights-only pass has no channels: s.values is empty and indexing it is undefined
  // (UBSan: reference binding to a null pointer, tests/sanitize_suite.sh).
  if (s.channels == 0) return;
  for (uint32_t j = 0; j < count; ++j)
    std::copy_n(&s.values[size_t(list[j].id) * s.channels], s.channels,
                &out[size_t(j) * s.channels]);
}

constexpr float kMinAlphaForDepth = 1e-6f;  // normalised depth is 0 below this accumulated alpha

}  // namespace gslift
