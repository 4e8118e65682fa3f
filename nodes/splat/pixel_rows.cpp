#include "nodes/splat/pixel_rows.hpp"

#include <algorithm>

#include "nodes/splat/render_cache.hpp"

namespace gslift {

void render_sampled_pixels(const PixelRowsView& rows, const float* attributes, int channels,
                           const std::vector<uint32_t>& pixels, float* out) {
  for (size_t k = 0; k < pixels.size(); ++k) {
    float* o = out + k * channels;
    std::fill(o, o + channels, 0.f);
    for (uint32_t e = rows.offsets[pixels[k]]; e < rows.offsets[pixels[k] + 1]; ++e) {
      const float* a = attributes + size_t(rows.ids[e]) * channels;
      const float w = rows.weights[e];
      for (int c = 0; c < channels; ++c) o[c] += w * a[c];
    }
  }
}

void backward_sampled_pixels(const PixelRowsView& rows, const std::vector<uint32_t>& pixels,
                             const float* grad, int channels, float* grad_attributes) {
  for (size_t k = 0; k < pixels.size(); ++k) {
    const float* g = grad + k * channels;
    for (uint32_t e = rows.offsets[pixels[k]]; e < rows.offsets[pixels[k] + 1]; ++e) {
      float* d = grad_attributes + size_t(rows.ids[e]) * channels;
      const float w = rows.weights[e];
      for (int c = 0; c < channels; ++c) d[c] += w * g[c];
    }
  }
}

PixelRows::PixelRows(const RenderCache& cache, float min_weight) {
  const auto& off = cache.pixel_offsets();
  const auto& ids = cache.ids();
  const auto& w = cache.weights();
  offsets_.reserve(off.size());
  offsets_.push_back(0);
  for (size_t p = 0; p + 1 < off.size(); ++p) {
    for (uint32_t e = off[p]; e < off[p + 1]; ++e)
      if (w[e] >= min_weight) {
        ids_.push_back(ids[e]);
        weights_.push_back(w[e]);
      }
    offsets_.push_back(static_cast<uint32_t>(ids_.size()));
  }
  ids_.shrink_to_fit();
  weights_.shrink_to_fit();
}

}  // namespace gslift
