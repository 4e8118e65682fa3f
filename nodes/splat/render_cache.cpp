// Vector width of the blending loops it shares with the rasterizer: see rasterizer_forward.cpp.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/render_cache.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Core>

#include "base/errors.hpp"
#include "nodes/splat/raster_state.hpp"

namespace gslift {

namespace {

constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();

// One contribution of a tile's blend: the entry's position j in the tile's raster list, the tile
// pixel and its weight.
struct Contribution {
  uint32_t j;
  uint32_t p;
  float w;
};

// Every contribution of every pixel of tile t into `out` (replacing what it held), in blending
// order: entry by entry, front to back (blend_tile, the forward pass's blending), so each pixel's
// come front to back. Both passes of the cache read a tile's contributions from here, so both
// run one compiled blending loop: with a loop of its own each (two instantiations), they can
// round differently (FMA contraction) and disagree on whether a pair blends, which the main job
// with `line_of_sight_weight: 0` met in its held-out evaluation. Out of line, so that no caller
// gets a copy of its own. Blending once and keeping every tile's contributions for the second
// pass instead raised the main job's peak memory by 60 MB.
__attribute__((noinline)) void tile_contributions(const RasterState& s, int t, TileBlend& blend,
                                                  std::vector<Contribution>& out) {
  out.clear();
  blend_tile(s, t, blend, [&](uint32_t j, int at, const float* w, const RowLanes&) {
    for (int x = 0; x < kLanes; ++x)
      if (blend.last[at + x] == j + 1) out.push_back({j, uint32_t(at + x), w[x]});
  });
}

// Image pixel of tile pixel p of a tile.
size_t image_pixel(const RasterState& s, const PixelRect& tile, uint32_t p) {
  return size_t(tile.y0 + int(p / kTileSize)) * s.width + size_t(tile.x0 + int(p % kTileSize));
}

// Calls f(Index{}, std::integral_constant<int, K>{}) with the pair index type and the channel
// count as compile-time constants where it is common (K = 0: any count), so the channel loops
// vectorise and the sums stay in registers.
template <class F>
void dispatch(bool wide, int channels, F&& f) {
  auto with_channels = [&](auto index) {
    switch (channels) {
      case 16:
        return f(index, std::integral_constant<int, 16>{});
      case 32:
        return f(index, std::integral_constant<int, 32>{});
      case 3:
        return f(index, std::integral_constant<int, 3>{});
      case 1:
        return f(index, std::integral_constant<int, 1>{});
      default:
        return f(index, std::integral_constant<int, 0>{});
    }
  };
  if (wide)
    with_channels(uint32_t{});
  else
    with_channels(uint16_t{});
}

}  // namespace

RenderCache::RenderCache(const RenderOutput& forward) {
  if (!forward.state) throw InputError("RenderCache: the forward output has no raster state");
  const RasterState& s = *forward.state;
  width_ = s.width;
  height_ = s.height;
  tiles_x_ = s.tiles_x;
  tiles_y_ = s.tiles_y;
  const size_t pixels = size_t(width_) * height_;
  const size_t n = s.projections.size();
  const int tiles = s.tile_count();

  // Pass 1: contributions per pixel, and which raster list entries contribute at all, numbered in
  // list (front-to-back) order: their position in the cache's tile list.
  std::vector<uint32_t> counts(pixels, 0);
  std::vector<uint32_t> position(s.tile_gaussians.size(), kUnused);
  std::vector<uint32_t> tile_counts(tiles);
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles), [&](const tbb::blocked_range<int>& r) {
    TileBlend blend;
    std::vector<Contribution> contributions;
    for (int t = r.begin(); t != r.end(); ++t) {
      uint32_t* pos = position.data() + s.tile_offsets[t];
      tile_contributions(s, t, blend, contributions);
      const PixelRect tile = tile_pixels(s, t);
      for (const Contribution& c : contributions) {
        ++counts[image_pixel(s, tile, c.p)];
        pos[c.j] = 0;
      }
      uint32_t next = 0;
      for (uint32_t j = 0; j < s.tile_offsets[t + 1] - s.tile_offsets[t]; ++j)
        if (pos[j] != kUnused) pos[j] = next++;
      tile_counts[t] = next;
    }
  });
  tile_offsets_.assign(size_t(tiles) + 1, 0);
  uint32_t longest = 0;
  for (int t = 0; t < tiles; ++t) {
    tile_offsets_[t + 1] = tile_offsets_[t] + tile_counts[t];
    longest = std::max(longest, tile_counts[t]);
  }
  pixel_offsets_.assign(pixels + 1, 0);
  for (size_t p = 0; p < pixels; ++p) {
    if (uint64_t(pixel_offsets_[p]) + counts[p] >= std::numeric_limits<uint32_t>::max())
      throw InputError("RenderCache: more than 2^32 (pixel, Gaussian) pairs in one view");
    pixel_offsets_[p + 1] = pixel_offsets_[p] + counts[p];
  }
  const bool wide = longest > (uint32_t(1) << 16);
  const size_t pairs = pixel_offsets_[pixels];
  ids_.resize(pairs);
  weights_.resize(pairs);
  (wide ? local32_.resize(pairs) : local16_.resize(pairs));
  entry_ids_.resize(tile_offsets_[tiles]);

  // Pass 2: fill the tile lists, and the rows at their offsets.
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles), [&](const tbb::blocked_range<int>& r) {
    TileBlend blend;
    std::vector<Contribution> contributions;
    for (int t = r.begin(); t != r.end(); ++t) {
      const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
      const uint32_t* pos = position.data() + s.tile_offsets[t];
      for (uint32_t j = 0; j < s.tile_offsets[t + 1] - s.tile_offsets[t]; ++j)
        if (pos[j] != kUnused) entry_ids_[tile_offsets_[t] + pos[j]] = list[j].id;
      tile_contributions(s, t, blend, contributions);
      const PixelRect tile = tile_pixels(s, t);
      for (const Contribution& c : contributions) {
        const size_t pix = image_pixel(s, tile, c.p);
        const uint32_t k = pixel_offsets_[pix + 1] - counts[pix]--;
        ids_[k] = list[c.j].id;
        weights_[k] = c.w;
        if (wide)
          local32_[k] = pos[c.j];
        else
          local16_[k] = uint16_t(pos[c.j]);
      }
    }
  });

  // Each Gaussian's entries in tile order (counting sort).
  gaussian_offsets_.assign(n + 1, 0);
  for (uint32_t id : entry_ids_) ++gaussian_offsets_[id + 1];
  for (size_t g = 0; g < n; ++g) gaussian_offsets_[g + 1] += gaussian_offsets_[g];
  std::vector<uint32_t> cursor(gaussian_offsets_.begin(), gaussian_offsets_.end() - 1);
  gaussian_entries_.resize(entry_ids_.size());
  for (uint32_t e = 0; e < entry_ids_.size(); ++e) gaussian_entries_[cursor[entry_ids_[e]]++] = e;
}

size_t RenderCache::bytes() const {
  return sizeof(uint32_t) *
             (pixel_offsets_.size() + ids_.size() + local32_.size() + tile_offsets_.size() +
              entry_ids_.size() + gaussian_offsets_.size() + gaussian_entries_.size()) +
         sizeof(uint16_t) * local16_.size() + sizeof(float) * weights_.size();
}

template <>
const uint16_t* RenderCache::local_ids<uint16_t>() const {
  return local16_.data();
}
template <>
const uint32_t* RenderCache::local_ids<uint32_t>() const {
  return local32_.data();
}

// Pixel rows [16 ty, 16 ty + 16) in row-major order (sequential reads of the pair arrays), from
// the attributes of that tile row's lists, gathered once into a contiguous buffer (their entries
// are contiguous in tile-major order; about 100 per tile at 50k Gaussians, so the buffer stays in
// the core's cache).
template <class Index, int kChannels>
void RenderCache::render_tiles(const float* attributes, int channels, float* out, int begin,
                               int end) const {
  const int C = kChannels > 0 ? kChannels : channels;
  constexpr int kLocal = kChannels > 0 ? kChannels : 1;
  using Vector = Eigen::Matrix<float, kLocal, 1>;
  const Index* local = local_ids<Index>();
  const float* w = weights_.data();
  std::vector<float> gathered;
  for (int ty = begin; ty != end; ++ty) {
    const uint32_t* tile_first = &tile_offsets_[size_t(ty) * tiles_x_];
    const uint32_t first = tile_first[0], count = tile_first[tiles_x_] - first;
    gathered.resize(size_t(count) * C);
    for (uint32_t e = 0; e < count; ++e)
      std::copy_n(attributes + size_t(entry_ids_[first + e]) * C, C, &gathered[size_t(e) * C]);
    for (int y = ty * kTileSize; y < std::min(height_, (ty + 1) * kTileSize); ++y)
      for (int x = 0; x < width_; ++x) {
        const size_t p = size_t(y) * width_ + x;
        // data() + offset, not &gathered[offset]: a tile row with no Gaussians leaves the buffer
        // empty, and indexing an empty vector is undefined even when nothing is read (UBSan).
        const float* tile = gathered.data() + size_t(tile_first[x / kTileSize] - first) * C;
        float* o = out + p * C;
        if constexpr (kChannels > 0) {
          // Eigen's fixed-size packets vectorise along the channels (GCC alone vectorises across
          // entries here, with costly shuffles).
          Vector acc = Vector::Zero();
          for (uint32_t k = pixel_offsets_[p]; k < pixel_offsets_[p + 1]; ++k)
            acc.noalias() += w[k] * Eigen::Map<const Vector>(tile + size_t(local[k]) * kLocal);
          Eigen::Map<Vector>{o} = acc;
        } else {
          std::fill_n(o, C, 0.f);
          for (uint32_t k = pixel_offsets_[p]; k < pixel_offsets_[p + 1]; ++k) {
            const float* a = tile + size_t(local[k]) * C;
            for (int c = 0; c < C; ++c) o[c] += w[k] * a[c];
          }
        }
      }
  }
}

void RenderCache::render(const float* attributes, int channels, float* out) const {
  dispatch(!local32_.empty(), channels, [&](auto index, auto fixed) {
    using Index = decltype(index);
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles_y_), [&](const tbb::blocked_range<int>& r) {
      render_tiles<Index, decltype(fixed)::value>(attributes, channels, out, r.begin(), r.end());
    });
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

// entry_grads row e (C values) = sum over the pixels of entry e's tile, in row-major order, of
// w * grad_out[pixel], for the entries of tile rows [begin, end).
template <class Index, int kChannels>
void RenderCache::backward_tiles(const float* grad_out, int channels, float* entry_grads, int begin,
                                 int end) const {
  const int C = kChannels > 0 ? kChannels : channels;
  constexpr int kLocal = kChannels > 0 ? kChannels : 1;
  using Vector = Eigen::Matrix<float, kLocal, 1>;
  const Index* local = local_ids<Index>();
  const float* w = weights_.data();
  for (int ty = begin; ty != end; ++ty) {
    const uint32_t* tile_first = &tile_offsets_[size_t(ty) * tiles_x_];
    std::fill(entry_grads + size_t(tile_first[0]) * C,
              entry_grads + size_t(tile_first[tiles_x_]) * C, 0.f);
    for (int y = ty * kTileSize; y < std::min(height_, (ty + 1) * kTileSize); ++y)
      for (int x = 0; x < width_; ++x) {
        const size_t p = size_t(y) * width_ + x;
        float* tile = entry_grads + size_t(tile_first[x / kTileSize]) * C;
        const float* g = grad_out + p * C;
        for (uint32_t k = pixel_offsets_[p]; k < pixel_offsets_[p + 1]; ++k) {
          float* row = tile + size_t(local[k]) * C;
          if constexpr (kChannels > 0)
            Eigen::Map<Vector>{row} += w[k] * Eigen::Map<const Vector>(g);
          else
            for (int c = 0; c < C; ++c) row[c] += w[k] * g[c];
        }
      }
  }
}

void RenderCache::backward(const float* grad_out, int channels, float* grad_attributes) const {
  const int C = channels;
  UninitVector<float> entry_grads(entry_ids_.size() * size_t(C));
  dispatch(!local32_.empty(), channels, [&](auto index, auto fixed) {
    using Index = decltype(index);
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles_y_), [&](const tbb::blocked_range<int>& r) {
      backward_tiles<Index, decltype(fixed)::value>(grad_out, channels, entry_grads.data(),
                                                    r.begin(), r.end());
    });
  });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, gaussian_count(), 256),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t g = r.begin(); g != r.end(); ++g) {
                        float* d = grad_attributes + g * C;
                        for (uint32_t i = gaussian_offsets_[g]; i < gaussian_offsets_[g + 1]; ++i) {
                          const float* row = &entry_grads[size_t(gaussian_entries_[i]) * C];
                          for (int c = 0; c < C; ++c) d[c] += row[c];
                        }
                      }
                    });
}

void add_blend_weights(const RenderOutput& forward, float* per_gaussian) {
  if (!forward.state) throw InputError("add_blend_weights: the forward output has no raster state");
  const RasterState& s = *forward.state;
  // One sum per tile-list entry, at its slot: a Gaussian's slots run in tile order.
  std::vector<float> slot_sums(s.slot_offsets.back(), 0.f);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, s.tile_count()), [&](const tbb::blocked_range<int>& r) {
        TileBlend blend;
        for (int t = r.begin(); t != r.end(); ++t) {
          const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
          // w is 0 in the lanes where entry j does not blend, and adding 0 leaves a
          // sum as it is.
          blend_tile(s, t, blend, [&](uint32_t j, int, const float* w, const RowLanes&) {
            float& sum = slot_sums[list[j].slot];
            for (int x = 0; x < kLanes; ++x) sum += w[x];
          });
        }
      });
  const size_t n = s.slot_offsets.size() - 1;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t g = r.begin(); g != r.end(); ++g)
                        for (uint32_t k = s.slot_offsets[g]; k < s.slot_offsets[g + 1]; ++k)
                          per_gaussian[g] += slot_sums[k];
                    });
}

}  // namespace gslift
