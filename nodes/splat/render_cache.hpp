// Render cache for frozen geometry (issue 4): the blend weights w_i = alpha_i T_i of one forward
// pass, stored per pixel in CSR form. With the geometry fixed, rendering any per-Gaussian linear
// attribute (instance features, class scores: LangOR Eq. 1, Proto-SaGa Eq. 5) is the sparse product
// F = W A, and its gradient dL/dA = W^T dL/dF, both far cheaper than rasterizing again.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "nodes/splat/rasterizer.hpp"

namespace gslift {

class RenderCache {
 public:
  // Records the weights of `forward` (any channel selection: the weights do not depend on it).
  // Throws InputError when forward has no raster state.
  explicit RenderCache(const RenderOutput& forward);

  int width() const { return width_; }
  int height() const { return height_; }
  size_t gaussian_count() const { return gaussian_offsets_.size() - 1; }
  size_t entries() const { return ids_.size(); }  // stored (pixel, Gaussian) pairs
  // Memory held, in bytes: both the per-pixel rows and their per-Gaussian transpose.
  size_t bytes() const;

  // out (H x W x channels) = sum over each pixel's pairs of w * attributes[id] (N x channels,
  // row-major). Parallel over pixel rows.
  void render(const float* attributes, int channels, float* out) const;
  std::vector<float> render(const std::vector<float>& attributes, int channels) const;

  // Adds W^T grad_out to grad_attributes (N x channels). Parallel over Gaussians, each summing
  // its pixels in row-major order, so the result does not depend on the thread count.
  void backward(const float* grad_out, int channels, float* grad_attributes) const;

  // Per-pixel rows: pixel p owns [pixel_offsets[p], pixel_offsets[p+1]) of ids/weights, front to
  // back.
  const std::vector<uint32_t>& pixel_offsets() const { return pixel_offsets_; }
  const std::vector<uint32_t>& ids() const { return ids_; }
  const std::vector<float>& weights() const { return weights_; }

 private:
  // backward() for Gaussians [begin, end); kChannels > 0 fixes the channel count at compile time.
  template <int kChannels>
  void transposed_rows(const float* grad_out, int channels, float* grad_attributes, size_t begin,
                       size_t end) const;

  int width_ = 0, height_ = 0;
  std::vector<uint32_t> pixel_offsets_;  // H x W + 1
  std::vector<uint32_t> ids_;
  std::vector<float> weights_;
  // Transpose (Gaussian -> pixels), for the deterministic gradient.
  std::vector<uint32_t> gaussian_offsets_;  // N + 1
  std::vector<uint32_t> pixels_;
  std::vector<float> pixel_weights_;
};

}  // namespace gslift
