// Vector width of the blending loops it shares with the rasterizer: see rasterizer_forward.cpp.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/pixel_rows.hpp"

#include <algorithm>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

namespace {

// The sampled pixels are in no order the cache can follow, and each list entry reads or adds to
// a random attribute row: the loops waited on those loads (perf annotate). So while sample k is
// summed, the attribute rows of sample k + 1 and the id and weight lists of sample k + 2 are
// prefetched (the order of the sums is unchanged).
void prefetch_lists(const PixelRowsView& rows, const std::vector<uint32_t>& pixels, size_t k) {
  if (k >= pixels.size()) return;
  const uint32_t begin = rows.offsets[pixels[k]];
  __builtin_prefetch(rows.ids + begin);
  __builtin_prefetch(rows.weights + begin);
}
void prefetch_attributes(const PixelRowsView& rows, const std::vector<uint32_t>& pixels, size_t k,
                         const float* attributes, int channels) {
  if (k >= pixels.size()) return;
  constexpr int kLineFloats = 16;  // 64-byte lines
  for (uint32_t e = rows.offsets[pixels[k]]; e < rows.offsets[pixels[k] + 1]; ++e) {
    const float* row = attributes + size_t(rows.ids[e]) * channels;
    for (int c = 0; c < channels; c += kLineFloats) __builtin_prefetch(row + c);
  }
}

}  // namespace

void render_sampled_pixels(const PixelRowsView& rows, const float* attributes, int channels,
                           const std::vector<uint32_t>& pixels, float* out) {
  for (size_t k = 0; k < pixels.size(); ++k) {
    prefetch_lists(rows, pixels, k + 2);
    prefetch_attributes(rows, pixels, k + 1, attributes, channels);
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
                             const float* grad, int channels, float* grad_attributes,
                             uint32_t id_begin, uint32_t id_end) {
  for (size_t k = 0; k < pixels.size(); ++k) {
    prefetch_lists(rows, pixels, k + 2);
    prefetch_attributes(rows, pixels, k + 1, grad_attributes, channels);
    const float* g = grad + k * channels;
    for (uint32_t e = rows.offsets[pixels[k]]; e < rows.offsets[pixels[k] + 1]; ++e) {
      const uint32_t id = rows.ids[e];
      if (id < id_begin || id >= id_end) continue;
      float* d = grad_attributes + size_t(id) * channels;
      const float w = rows.weights[e];
      for (int c = 0; c < channels; ++c) d[c] += w * g[c];
    }
  }
}

PixelRows::PixelRows(const RenderOutput& forward, float min_weight) {
  if (!forward.state) throw InputError("PixelRows: the forward output has no raster state");
  const RasterState& s = *forward.state;
  const int tiles = s.tile_count();
  // One blending pass: each tile's kept pairs, sorted by tile pixel (stable, so each pixel's stay
  // front to back), then copied to the image's rows. A count pass and a fill pass would be two
  // instantiations of the blending loop, which the compiler may round differently (FMA
  // contraction) and so disagree on a weight at min_weight.
  struct TilePairs {
    uint32_t offsets[kTilePixels + 1];
    std::vector<uint32_t> ids;
    std::vector<float> weights;
  };
  std::vector<TilePairs> per_tile(tiles);
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles), [&](const tbb::blocked_range<int>& r) {
    TileBlend blend;
    std::vector<uint8_t> pixel;
    std::vector<uint32_t> ids;
    std::vector<float> weights;
    for (int t = r.begin(); t != r.end(); ++t) {
      const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
      pixel.clear();
      ids.clear();
      weights.clear();
      blend_tile(s, t, blend, [&](uint32_t j, int at, const float* w, const RowLanes&) {
        for (int x = 0; x < kLanes; ++x)
          if (blend.last[at + x] == j + 1 && w[x] >= min_weight) {
            pixel.push_back(uint8_t(at + x));
            ids.push_back(list[j].id);
            weights.push_back(w[x]);
          }
      });
      TilePairs& out = per_tile[t];
      std::fill(std::begin(out.offsets), std::end(out.offsets), 0u);
      for (const uint8_t p : pixel) ++out.offsets[p + 1];
      for (int p = 0; p < kTilePixels; ++p) out.offsets[p + 1] += out.offsets[p];
      uint32_t cursor[kTilePixels];
      std::copy_n(out.offsets, kTilePixels, cursor);
      out.ids.resize(ids.size());
      out.weights.resize(ids.size());
      for (size_t k = 0; k < pixel.size(); ++k) {
        const uint32_t to = cursor[pixel[k]]++;
        out.ids[to] = ids[k];
        out.weights[to] = weights[k];
      }
    }
  });
  const size_t pixels = size_t(s.width) * s.height;
  offsets_.assign(pixels + 1, 0);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const TilePairs& tile = per_tile[(y / kTileSize) * s.tiles_x + x / kTileSize];
      const int p = (y % kTileSize) * kTileSize + x % kTileSize;
      const size_t pix = size_t(y) * s.width + x;
      const uint32_t count = tile.offsets[p + 1] - tile.offsets[p];
      if (uint64_t(offsets_[pix]) + count >= std::numeric_limits<uint32_t>::max())
        throw InputError("PixelRows: more than 2^32 (pixel, Gaussian) pairs in one view");
      offsets_[pix + 1] = offsets_[pix] + count;
    }
  ids_.resize(offsets_[pixels]);
  weights_.resize(offsets_[pixels]);
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t != r.end(); ++t) {
      const TilePairs& tile = per_tile[t];
      const PixelRect rect = tile_pixels(s, t);
      for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x) {
          const int p = (y - rect.y0) * kTileSize + (x - rect.x0);
          const size_t to = offsets_[size_t(y) * s.width + x];
          std::copy(tile.ids.begin() + tile.offsets[p], tile.ids.begin() + tile.offsets[p + 1],
                    ids_.begin() + to);
          std::copy(tile.weights.begin() + tile.offsets[p],
                    tile.weights.begin() + tile.offsets[p + 1], weights_.begin() + to);
        }
      std::vector<uint32_t>().swap(per_tile[t].ids);
      std::vector<float>().swap(per_tile[t].weights);
    }
  });
}

}  // namespace gslift
