// Render cache for frozen geometry: the blend weights w_i = alpha_i T_i of one forward
// pass, stored per pixel in CSR form. With the geometry fixed, rendering any per-Gaussian linear
// attribute (instance features, class scores: LangOR Eq. 1, Proto-SaGa Eq. 5) is the sparse product
// F = W A, and its gradient dL/dA = W^T dL/dF, both far cheaper than rasterizing again.
//
// Both products run tile by tile: each 16x16 tile keeps the list of Gaussians that contribute to
// one of its pixels, and each (pixel, Gaussian) pair also stores its Gaussian's position in that
// list (16 bits when every list fits). render() gathers the attributes of a row of tiles' lists
// once into a contiguous buffer and sums from there, reading 6 bytes per pair plus cache-resident
// rows, instead of 8 bytes per pair plus a random attribute row; backward() sums each list entry's
// pixels into a per-entry row and then each Gaussian's entries in tile order (deterministic at any
// thread count, with no per-pair transpose to hold).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "nodes/splat/pixel_rows.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

// Adds to per_gaussian[g] (one value per Gaussian of the rendered model) Gaussian g's blend
// weights w = alpha T summed over the pixels of `forward`: how much of the view it explains, W^T 1.
// The sums of RenderCache(forward).backward(ones, 1, per_gaussian) in its order (each tile list
// entry's pixels in row-major order, then a Gaussian's entries in tile order; bit for bit on the
// tests and the main job, as long as the compiler rounds both blending loops alike), from one
// blending pass with one float per tile-list entry instead of the cache's per-pixel rows (about 10
// bytes per (pixel, Gaussian) pair: 100 MB for a 640x480 view of 50k Gaussians). Deterministic at
// any thread count. Throws InputError when forward has no raster state.
void add_blend_weights(const RenderOutput& forward, float* per_gaussian);

class RenderCache {
 public:
  // Records the weights of `forward` (any channel selection: the weights do not depend on it).
  // Throws InputError when forward has no raster state.
  explicit RenderCache(const RenderOutput& forward);

  int width() const { return width_; }
  int height() const { return height_; }
  size_t gaussian_count() const { return gaussian_offsets_.size() - 1; }
  size_t entries() const { return ids_.size(); }             // stored (pixel, Gaussian) pairs
  size_t tile_entries() const { return entry_ids_.size(); }  // (tile, contributing Gaussian) pairs
  // Memory held, in bytes: the per-pixel rows (id, weight, position in the tile list) and the
  // tile lists with their per-Gaussian index.
  size_t bytes() const;

  // out (H x W x channels) = sum over each pixel's pairs of w * attributes[id] (N x channels,
  // row-major). Parallel over rows of tiles.
  void render(const float* attributes, int channels, float* out) const;
  std::vector<float> render(const std::vector<float>& attributes, int channels) const;

  // Adds W^T grad_out to grad_attributes (N x channels). Parallel over rows of tiles, then over
  // Gaussians; every sum runs in a fixed order, so the result does not depend on the thread count.
  void backward(const float* grad_out, int channels, float* grad_attributes) const;

  // The same products restricted to sampled pixels (row-major indices): out (pixels.size() x
  // channels) = W_S attributes, and its adjoint grad_attributes += W_S^T grad.
  void render_pixels(const float* attributes, int channels, const std::vector<uint32_t>& pixels,
                     float* out) const {
    render_sampled_pixels(pixel_rows(), attributes, channels, pixels, out);
  }
  void backward_pixels(const std::vector<uint32_t>& pixels, const float* grad, int channels,
                       float* grad_attributes) const {
    backward_sampled_pixels(pixel_rows(), pixels, grad, channels, grad_attributes);
  }

  // Per-pixel rows: pixel p owns [pixel_offsets[p], pixel_offsets[p+1]) of ids/weights, front to
  // back.
  const std::vector<uint32_t>& pixel_offsets() const { return pixel_offsets_; }
  const std::vector<uint32_t>& ids() const { return ids_; }
  const std::vector<float>& weights() const { return weights_; }
  PixelRowsView pixel_rows() const { return {pixel_offsets_.data(), ids_.data(), weights_.data()}; }

 private:
  template <class Index>
  const Index* local_ids() const;
  template <class Index, int kChannels>
  void render_tiles(const float* attributes, int channels, float* out, int begin, int end) const;
  template <class Index, int kChannels>
  void backward_tiles(const float* grad_out, int channels, float* entry_grads, int begin,
                      int end) const;

  int width_ = 0, height_ = 0, tiles_x_ = 0, tiles_y_ = 0;
  std::vector<uint32_t> pixel_offsets_;  // H x W + 1
  std::vector<uint32_t> ids_;
  std::vector<float> weights_;
  // Per pair, the position of its Gaussian in its tile's list: local16_ when every list has at
  // most 2^16 entries, else local32_ (the other one is empty).
  std::vector<uint16_t> local16_;
  std::vector<uint32_t> local32_;
  // Per tile, the contributing Gaussians front to back: tile t owns entries
  // [tile_offsets_[t], tile_offsets_[t+1]) of entry_ids_.
  std::vector<uint32_t> tile_offsets_;
  std::vector<uint32_t> entry_ids_;
  // Per Gaussian, its entries in tile order: g owns gaussian_entries_[gaussian_offsets_[g] ..
  // gaussian_offsets_[g+1]), for the deterministic gradient reduction.
  std::vector<uint32_t> gaussian_offsets_;  // N + 1
  std::vector<uint32_t> gaussian_entries_;
};

}  // namespace gslift
