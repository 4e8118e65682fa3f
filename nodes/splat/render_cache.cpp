// Vector width of the blending loops it shares with the rasterizer: see rasterizer.cpp.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/render_cache.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Core>

#include "nodes/splat/raster_state.hpp"
#include "runtime/node.hpp"

namespace gslift {

namespace {

// Calls visit(pixel, id, w) for every contribution of every pixel of tile t; each pixel's
// contributions come front to back (blend_tile, the forward pass's blending).
template <class Visit>
void visit_tile(const RasterState& s, int t, TileBlend& blend, Visit&& visit) {
  const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
  const PixelRect tile = tile_pixels(s, t);
  blend_tile(s, t, blend, [&](uint32_t j, int at, const float* w) {
    for (int x = 0; x < kLanes; ++x)
      if (blend.last[at + x] == j + 1) {
        const int p = at + x;
        visit(size_t(tile.y0 + p / kTileSize) * s.width + tile.x0 + x, list[j].id, w[x]);
      }
  });
}

// out_row[c] = sum_k w_k attributes[id_k][c]; channels a template constant where it is common, so
// the channel loop vectorises and the sums stay in registers.
template <int kChannels>
void product_rows(const RenderCache& cache, const float* attributes, int channels, float* out,
                  size_t begin, size_t end) {
  const int C = kChannels > 0 ? kChannels : channels;
  const auto& off = cache.pixel_offsets();
  const uint32_t* ids = cache.ids().data();
  const float* w = cache.weights().data();
  constexpr int kLocal = kChannels > 0 ? kChannels : 1;
  using Vector = Eigen::Matrix<float, kLocal, 1>;
  for (size_t p = begin; p < end; ++p) {
    float* o = out + p * C;
    if (kChannels > 0) {
      // Eigen's fixed-size packets vectorise along the channels (GCC alone vectorises across
      // entries here, with costly shuffles).
      Vector acc = Vector::Zero();
      for (uint32_t k = off[p]; k < off[p + 1]; ++k)
        acc.noalias() += w[k] * Eigen::Map<const Vector>(attributes + size_t(ids[k]) * kLocal);
      Eigen::Map<Vector>{o} = acc;
    } else {
      std::fill_n(o, C, 0.f);
      for (uint32_t k = off[p]; k < off[p + 1]; ++k) {
        const float* a = attributes + size_t(ids[k]) * C;
        const float wk = w[k];
        for (int c = 0; c < C; ++c) o[c] += wk * a[c];
      }
    }
  }
}

}  // namespace

RenderCache::RenderCache(const RenderOutput& forward) {
  if (!forward.state) throw InputError("RenderCache: the forward output has no raster state");
  const RasterState& s = *forward.state;
  width_ = s.width;
  height_ = s.height;
  const size_t pixels = size_t(width_) * height_;
  const size_t n = s.projections.size();

  // Pass 1: contributions per pixel; pass 2: fill the rows at their offsets.
  std::vector<uint32_t> counts(pixels, 0);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, s.tile_count()), [&](const tbb::blocked_range<int>& r) {
        TileBlend blend;
        for (int t = r.begin(); t != r.end(); ++t)
          visit_tile(s, t, blend, [&](size_t pix, uint32_t, float) { ++counts[pix]; });
      });
  pixel_offsets_.assign(pixels + 1, 0);
  for (size_t p = 0; p < pixels; ++p) {
    if (uint64_t(pixel_offsets_[p]) + counts[p] >= std::numeric_limits<uint32_t>::max())
      throw InputError("RenderCache: more than 2^32 (pixel, Gaussian) pairs in one view");
    pixel_offsets_[p + 1] = pixel_offsets_[p] + counts[p];
  }
  ids_.resize(pixel_offsets_[pixels]);
  weights_.resize(ids_.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, s.tile_count()),
                    [&](const tbb::blocked_range<int>& r) {
                      TileBlend blend;
                      for (int t = r.begin(); t != r.end(); ++t)
                        visit_tile(s, t, blend, [&](size_t pix, uint32_t id, float w) {
                          const uint32_t k = pixel_offsets_[pix + 1] - counts[pix]--;
                          ids_[k] = id;
                          weights_[k] = w;
                        });
                    });

  // Transpose by counting sort over Gaussians, scanning pixels in order.
  gaussian_offsets_.assign(n + 1, 0);
  for (uint32_t id : ids_) ++gaussian_offsets_[id + 1];
  for (size_t g = 0; g < n; ++g) gaussian_offsets_[g + 1] += gaussian_offsets_[g];
  std::vector<uint32_t> cursor(gaussian_offsets_.begin(), gaussian_offsets_.end() - 1);
  pixels_.resize(ids_.size());
  pixel_weights_.resize(ids_.size());
  for (size_t p = 0; p < pixels; ++p)
    for (uint32_t k = pixel_offsets_[p]; k < pixel_offsets_[p + 1]; ++k) {
      const uint32_t dst = cursor[ids_[k]]++;
      pixels_[dst] = uint32_t(p);
      pixel_weights_[dst] = weights_[k];
    }
}

size_t RenderCache::bytes() const {
  return sizeof(uint32_t) *
             (pixel_offsets_.size() + ids_.size() + gaussian_offsets_.size() + pixels_.size()) +
         sizeof(float) * (weights_.size() + pixel_weights_.size());
}

void RenderCache::render(const float* attributes, int channels, float* out) const {
  const size_t pixels = size_t(width_) * height_;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, pixels, size_t(width_)),
      [&](const tbb::blocked_range<size_t>& r) {
        switch (channels) {
          case 16:
            return product_rows<16>(*this, attributes, channels, out, r.begin(), r.end());
          case 32:
            return product_rows<32>(*this, attributes, channels, out, r.begin(), r.end());
          case 3:
            return product_rows<3>(*this, attributes, channels, out, r.begin(), r.end());
          case 1:
            return product_rows<1>(*this, attributes, channels, out, r.begin(), r.end());
          default:
            return product_rows<0>(*this, attributes, channels, out, r.begin(), r.end());
        }
      });
}

std::vector<float> RenderCache::render(const std::vector<float>& attributes, int channels) const {
  if (channels <= 0 || attributes.size() != gaussian_count() * size_t(channels))
    throw InputError("RenderCache: attributes have " + std::to_string(attributes.size()) +
                     " values, expected " + std::to_string(gaussian_count()) + " x " +
                     std::to_string(channels));
  std::vector<float> out(size_t(width_) * height_ * channels);
  render(attributes.data(), channels, out.data());
  return out;
}

void RenderCache::backward(const float* grad_out, int channels, float* grad_attributes) const {
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, gaussian_count(), 256),
      [&](const tbb::blocked_range<size_t>& r) {
        switch (channels) {
          case 16:
            return transposed_rows<16>(grad_out, channels, grad_attributes, r.begin(), r.end());
          case 32:
            return transposed_rows<32>(grad_out, channels, grad_attributes, r.begin(), r.end());
          default:
            return transposed_rows<0>(grad_out, channels, grad_attributes, r.begin(), r.end());
        }
      });
}

template <int kChannels>
void RenderCache::transposed_rows(const float* grad_out, int channels, float* grad_attributes,
                                  size_t begin, size_t end) const {
  const int C = kChannels > 0 ? kChannels : channels;
  constexpr int kLocal = kChannels > 0 ? kChannels : 1;
  using Vector = Eigen::Matrix<float, kLocal, 1>;
  for (size_t g = begin; g != end; ++g) {
    float* d = grad_attributes + g * C;
    if (kChannels > 0) {
      Vector acc = Vector::Zero();
      for (uint32_t k = gaussian_offsets_[g]; k < gaussian_offsets_[g + 1]; ++k)
        acc.noalias() +=
            pixel_weights_[k] * Eigen::Map<const Vector>(grad_out + size_t(pixels_[k]) * kLocal);
      Eigen::Map<Vector>{d} += acc;
    } else {
      for (uint32_t k = gaussian_offsets_[g]; k < gaussian_offsets_[g + 1]; ++k) {
        const float* go = grad_out + size_t(pixels_[k]) * C;
        const float w = pixel_weights_[k];
        for (int c = 0; c < C; ++c) d[c] += w * go[c];
      }
    }
  }
}

}  // namespace gslift
