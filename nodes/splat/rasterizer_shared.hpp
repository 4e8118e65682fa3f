// What the rasterizer's forward pass (rasterizer_forward.cpp) and backward pass
// (rasterizer_backward.cpp) share: the model check, the activations, the SH colour of a Gaussian
// and the gathering of a tile's per-Gaussian values. Internal to nodes/splat.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
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

// Copies a tile's per-Gaussian values into a contiguous buffer (cache-friendly blending). Each
// row goes in pieces of kValuePiece floats, one fixed-size copy each, so the last piece may read
// and write up to kValuePiece - 1 floats past the row: RasterState::values and `out` carry that
// much slack (a memmove call per row of 7 floats was 2% of the main job's samples). The rows are
// in no order the cache can follow: the row 8 entries ahead is prefetched.
inline void gather_values(const RasterState& s, const TileGaussian* list, uint32_t count,
                          std::vector<float>& out) {
  const int C = s.channels;
  out.resize(size_t(count) * C + kValuePiece);
  if (C == 0) return;  // a weights-only pass: nothing to copy
  constexpr uint32_t kAhead = 8;
  for (uint32_t j = 0; j < count; ++j) {
    if (j + kAhead < count) __builtin_prefetch(&s.values[size_t(list[j + kAhead].id) * C]);
    const float* from = &s.values[size_t(list[j].id) * C];
    float* to = &out[size_t(j) * C];
    for (int c = 0; c < C; c += kValuePiece)
      std::memcpy(to + c, from + c, kValuePiece * sizeof(float));
  }
}

constexpr float kMinAlphaForDepth = 1e-6f;  // normalised depth is 0 below this accumulated alpha

}  // namespace gslift
