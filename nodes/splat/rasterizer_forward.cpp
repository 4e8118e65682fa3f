// Forward pass of the rasterizer (rasterizer.hpp): projection, tile binning, depth sort and
// front-to-back blending of every requested channel.
// The blending loops are written for 16 lanes (raster_state.hpp: kLanes); GCC's default for
// -march=native on AVX-512 machines splits them into two 256-bit halves. One 512-bit register is
// 1.1x faster on the 50k bench; the option only matters where AVX-512 is enabled.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/rasterizer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer_shared.hpp"
#include "nodes/splat/sh.hpp"

namespace gslift {

namespace {

// Pixels [x0, x1) x [y0, y1) a projected Gaussian is blended into, and the tiles they touch.
struct BlendRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;      // pixels, clipped to the image
  int tx0 = 0, ty0 = 0, tx1 = 0, ty1 = 0;  // tiles
  uint32_t tiles() const {
    return tx1 > tx0 && ty1 > ty0 ? uint32_t((tx1 - tx0) * (ty1 - ty0)) : 0u;
  }
};

// 3DGS evaluates a Gaussian at every pixel of the tiles its 3-sigma square (half-width = radius)
// touches and skips alpha < min_alpha there. The pixels where alpha = o exp(-0.5 d^T conic d) can
// reach min_alpha lie in the bounding box of the ellipse d^T cov^-1 d <= 2 ln(o / min_alpha), of
// half-widths sqrt(2 ln(o / min_alpha) cov_xx) and likewise for y; intersecting the two gives the
// same image with far fewer evaluations, and fewer tiles, for faint and flat Gaussians.
BlendRect blend_rect(const ProjectedGaussian& p, float opacity, float min_alpha, int width,
                     int height) {
  // Clamp in float before converting: a Gaussian near the image plane can project anywhere.
  auto tile = [](float coord, int size) {
    return int(std::clamp(std::floor(coord / kTileSize), 0.f, float((size - 1) / kTileSize)));
  };
  const float r = float(p.radius);
  const float mx = p.mean2d.x(), my = p.mean2d.y();
  if (mx + r < 0.f || my + r < 0.f || mx - r >= width || my - r >= height) return BlendRect{};
  BlendRect b;
  b.x0 = tile(mx - r, width) * kTileSize;
  b.y0 = tile(my - r, height) * kTileSize;
  b.x1 = std::min(width, (tile(mx + r, width) + 1) * kTileSize);
  b.y1 = std::min(height, (tile(my + r, height) + 1) * kTileSize);
  if (min_alpha > 0.f) {
    if (opacity < min_alpha) return BlendRect{};
    const float k = 2.f * std::log(opacity / min_alpha);
    const float hx = std::sqrt(k * p.cov2d[0]), hy = std::sqrt(k * p.cov2d[2]);
    // Pixel x is inside when its centre x + 0.5 lies in [mx - hx, mx + hx].
    auto first = [](float lo, int size) {
      return int(std::clamp(std::ceil(lo - 0.5f), 0.f, float(size)));
    };
    auto end = [](float hi, int size) {
      return int(std::clamp(std::floor(hi - 0.5f) + 1.f, 0.f, float(size)));
    };
    b.x0 = std::max(b.x0, first(mx - hx, width));
    b.x1 = std::min(b.x1, end(mx + hx, width));
    b.y0 = std::max(b.y0, first(my - hy, height));
    b.y1 = std::min(b.y1, end(my + hy, height));
  }
  if (b.x1 <= b.x0 || b.y1 <= b.y0) return BlendRect{};
  b.tx0 = b.x0 / kTileSize;
  b.ty0 = b.y0 / kTileSize;
  b.tx1 = (b.x1 - 1) / kTileSize + 1;
  b.ty1 = (b.y1 - 1) / kTileSize + 1;
  return b;
}

// Sort key of a depth: unsigned order of the result = float order of the depth (sign bit flipped
// for positive depths, all bits for negative ones; -0 becomes +0 first).
uint32_t depth_order(float depth) {
  uint32_t bits;
  const float normalised = depth + 0.f;
  std::memcpy(&bits, &normalised, sizeof bits);
  return bits ^ ((bits >> 31) != 0u ? 0xffffffffu : 0x80000000u);
}

// Projects every Gaussian, computes its blended values and fills the depth-sorted tile lists.
// Gaussian g's channel values (rgb from its SH at this view, depth, normal, features, alpha) in
// the state's layout.
void write_channel_values(const GaussianModel& model, const ViewTransform& view,
                          const ProjectedGaussian& p, size_t g, RasterState& s) {
  const int K = GaussianModel::sh_coeffs(model.sh_degree);
  const int D = model.feature_dim;
  float* v = s.values.data() + g * s.channels;  // without channels, values holds the slack only
  if (s.rgb_offset >= 0) {
    float basis[kMaxShCoeffs];
    float length;
    sh_basis(s.sh_degree, view_direction(view, &model.means[3 * g], length), basis);
    const Eigen::Vector3f c = sh_colour(&model.sh[g * K * 3], s.sh_degree, basis);
    for (int k = 0; k < 3; ++k) v[s.rgb_offset + k] = std::max(c[k], 0.f);
  }
  if (s.depth_offset >= 0) v[s.depth_offset] = p.depth;
  if (s.normal_offset >= 0)
    for (int k = 0; k < 3; ++k) v[s.normal_offset + k] = p.normal[k];
  for (int f = 0; s.feature_offset >= 0 && f < D; ++f)
    v[s.feature_offset + f] = model.features[g * D + f];
  if (s.alpha_offset >= 0) v[s.alpha_offset] = 1.f;
}

// The rows of an entry's [e.y0, e.y1) where some pixel of a strip of columns [x0, x1) can pass
// blend_row's test power >= power_min. The 3-sigma rectangle is tight for the whole footprint, but
// a slanted footprint meets each tile's columns in fewer rows: in the first 100 steps of the main
// job 16% of the rows the backward pass visited had no pixel that could blend (counted), and every
// blending loop (forward, backward, render cache, the line-of-sight and pruning passes) skips them
// for free when the entry's rows say so. A skipped row's lanes would all have been masked out, so
// the results are the same bit for bit.
// With q(d) = A dx^2 + 2B dx dy + C dy^2 (power = -q / 2), the pixels can blend where
// q <= k = -2 power_min: an ellipse, whose intersection with the columns' strip of dx is convex,
// so its rows span from its lowest to its highest point: the ellipse's own extremes where they
// lie in the strip, else the ends of its chords along the strip's edges. In double, with k and
// the rows widened against the float rounding of the lanes' own sums; a degenerate conic keeps
// its rectangle. The extremes are the entry's, found once for all its strips.
class NarrowedRows {
 public:
  explicit NarrowedRows(const TileGaussian& e) : e_(e), A_(e.A), B_(e.B), C_(e.C) {
    const double det = A_ * C_ - B_ * B_;
    k_ = -2.0 * double(e.power_min) * (1 + 1e-3) + 1e-3;
    degenerate_ = !(A_ > 0) || !(C_ > 0) || !(det > 0) || !(k_ > 0) || !std::isfinite(k_) ||
                  !std::isfinite(det);
    if (degenerate_) return;
    const double extreme = std::sqrt(k_ * A_ / det);  // at dx = -B dy / A
    for (int i = 0; i < 2; ++i) {
      extreme_dy_[i] = i == 0 ? -extreme : extreme;
      extreme_dx_[i] = -B_ * extreme_dy_[i] / A_;
    }
  }

  // [y0, y1) for the columns [x0, x1); y1 = y0 when no row can blend there.
  std::array<int16_t, 2> in_columns(int x0, int x1) const {
    if (degenerate_) return {e_.y0, e_.y1};
    const double dx_min = double(e_.mx) - (x1 - 0.5), dx_max = double(e_.mx) - (x0 + 0.5);
    double dy_min = std::numeric_limits<double>::infinity(), dy_max = -dy_min;
    for (int i = 0; i < 2; ++i)
      if (extreme_dx_[i] >= dx_min && extreme_dx_[i] <= dx_max) {
        dy_min = std::min(dy_min, extreme_dy_[i]);
        dy_max = std::max(dy_max, extreme_dy_[i]);
      }
    for (const double dx : {dx_min, dx_max}) {  // C dy^2 + 2 B dx dy + (A dx^2 - k) <= 0
      const double disc = B_ * B_ * dx * dx - C_ * (A_ * dx * dx - k_);
      if (!(disc >= 0)) continue;
      const double root = std::sqrt(disc);
      dy_min = std::min(dy_min, (-B_ * dx - root) / C_);
      dy_max = std::max(dy_max, (-B_ * dx + root) / C_);
    }
    if (!(dy_min <= dy_max)) return {e_.y0, e_.y0};
    // dy = my - (y + 0.5); one row more either side.
    const double first = std::floor(double(e_.my) - 0.5 - dy_max) - 1;
    const double last = std::ceil(double(e_.my) - 0.5 - dy_min) + 1;
    const auto y0 = int16_t(std::max<double>(e_.y0, std::min<double>(first, e_.y1)));
    return {y0, int16_t(std::max<double>(y0, std::min<double>(last + 1, e_.y1)))};
  }

 private:
  const TileGaussian& e_;
  double A_, B_, C_, k_;
  bool degenerate_;
  double extreme_dx_[2], extreme_dy_[2];
};

// The Gaussians that touch some tile, front to back: ascending depth_order, ties by index. A
// stable LSD radix sort of the indices (ascending) by the 32-bit key, a byte per pass.
std::vector<uint32_t> depth_sorted(const std::vector<BlendRect>& rects,
                                   const std::vector<ProjectedGaussian>& projections) {
  std::vector<uint32_t> order, keys, next_order, next_keys;
  order.reserve(rects.size());
  keys.reserve(rects.size());
  for (size_t g = 0; g < rects.size(); ++g)
    if (rects[g].tiles() > 0) {
      order.push_back(uint32_t(g));
      keys.push_back(depth_order(projections[g].depth));
    }
  next_order.resize(order.size());
  next_keys.resize(keys.size());
  for (int shift = 0; shift < 32; shift += 8) {
    std::array<uint32_t, 257> starts{};
    for (const uint32_t k : keys) ++starts[((k >> shift) & 0xffu) + 1];
    if (std::find(starts.begin() + 1, starts.end(), uint32_t(keys.size())) != starts.end())
      continue;  // every key has the same byte here: the pass would keep the order
    for (int b = 0; b < 256; ++b) starts[b + 1] += starts[b];
    for (size_t i = 0; i < keys.size(); ++i) {
      const uint32_t at = starts[(keys[i] >> shift) & 0xffu]++;
      next_order[at] = order[i];
      next_keys[at] = keys[i];
    }
    order.swap(next_order);
    keys.swap(next_keys);
  }
  return order;
}

// The Gaussians of each tile's list, front to back, tile by tile; sets s.tile_offsets. `order`:
// the Gaussians that touch some tile, by depth (depth_sorted). A counting sort of the (tile,
// Gaussian) pairs by tile in that order, in parallel over a fixed number of blocks of the order:
// each block counts its pairs per tile, and block b's pairs of tile t go after those of blocks
// < b, so each tile's list comes in depth order whatever the thread count. (Serial, the two
// passes were 1.5% of the main job, with the second core idle.)
UninitVector<uint32_t> listed_by_tile(const std::vector<BlendRect>& rects,
                                      const std::vector<uint32_t>& order, RasterState& s) {
  const int tiles = s.tile_count();
  // Both passes read the rectangles' tiles in depth order, gathered once.
  struct TileSpan {
    int tx0, ty0, tx1, ty1;
  };
  UninitVector<TileSpan> spans(order.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, order.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) {
                        const BlendRect& rect = rects[order[i]];
                        spans[i] = {rect.tx0, rect.ty0, rect.tx1, rect.ty1};
                      }
                    });
  constexpr size_t kBlocks = 8;
  const size_t block_size = (order.size() + kBlocks - 1) / kBlocks;
  std::vector<uint32_t> cursor(kBlocks * size_t(tiles), 0);  // [block][tile]
  auto for_blocks = [&](auto&& body) {
    tbb::parallel_for(size_t(0), kBlocks, [&](size_t b) {
      uint32_t* block_cursor = &cursor[b * size_t(tiles)];
      for (size_t i = b * block_size; i < std::min(order.size(), (b + 1) * block_size); ++i) {
        const TileSpan& span = spans[i];
        for (int ty = span.ty0; ty < span.ty1; ++ty)
          for (int tx = span.tx0; tx < span.tx1; ++tx)
            body(order[i], block_cursor[ty * s.tiles_x + tx]);
      }
    });
  };
  for_blocks([](uint32_t, uint32_t& count) { ++count; });
  s.tile_offsets.assign(tiles + 1, 0);
  uint32_t start = 0;
  for (int t = 0; t < tiles; ++t) {
    s.tile_offsets[t] = start;
    for (size_t b = 0; b < kBlocks; ++b) {
      const uint32_t count = cursor[b * size_t(tiles) + size_t(t)];
      cursor[b * size_t(tiles) + size_t(t)] = start;
      start += count;
    }
  }
  s.tile_offsets[tiles] = start;
  UninitVector<uint32_t> listed(s.slot_offsets.back());
  for_blocks([&](uint32_t g, uint32_t& next) { listed[next++] = g; });
  return listed;
}

// Per slot of a Gaussian whose rectangle spans several tile columns, its rows in the slot's
// column (NarrowedRows: the same in every tile of the column); a rectangle within one column has
// no rows to spare, and its slots are left unset.
UninitVector<std::array<int16_t, 2>> narrowed_slot_rows(const std::vector<BlendRect>& rects,
                                                        const UninitVector<TileGaussian>& entries,
                                                        const RasterState& s) {
  UninitVector<std::array<int16_t, 2>> slot_rows(s.slot_offsets.back());
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, rects.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t g = r.begin(); g != r.end(); ++g) {
          const BlendRect& rect = rects[g];
          const int columns = rect.tx1 - rect.tx0;
          if (rect.tiles() == 0 || columns == 1) continue;
          const NarrowedRows narrowed(entries[g]);
          for (int c = 0; c < columns; ++c) {
            const int tx = rect.tx0 + c;
            const std::array<int16_t, 2> rows = narrowed.in_columns(
                std::max(rect.x0, tx * kTileSize), std::min(rect.x1, (tx + 1) * kTileSize));
            for (int row = 0; row < rect.ty1 - rect.ty0; ++row)
              slot_rows[s.slot_offsets[g] + uint32_t(row * columns + c)] = rows;
          }
        }
      });
  return slot_rows;
}

// The tile lists of binned Gaussians (their screen rectangles and list entries; each entry's slot
// is set to the Gaussian's first slot here).
void sort_tile_lists(const std::vector<BlendRect>& rects, UninitVector<TileGaussian>& entries,
                     RasterState& s) {
  // Slots: Gaussian g owns one per tile of its rectangle, row by row. Tile lists: the Gaussians
  // sorted once by depth (ties by index, so the order never depends on scheduling), then a
  // counting sort of the (tile, Gaussian) pairs by tile in that order, which leaves each tile's
  // list front to back. (Sorting each tile's list instead sorted every Gaussian once per tile it
  // touches, about three times: 2.5% of the main job.)
  const size_t n = rects.size();
  s.slot_offsets.assign(n + 1, 0);
  for (size_t g = 0; g < n; ++g) {
    const BlendRect& rect = rects[g];
    if (uint64_t(s.slot_offsets[g]) + rect.tiles() >= std::numeric_limits<uint32_t>::max())
      throw InputError("rasterizer: more than 2^32 Gaussian-tile pairs");
    s.slot_offsets[g + 1] = s.slot_offsets[g] + rect.tiles();
    if (rect.tiles() > 0) entries[g].slot = s.slot_offsets[g];
  }
  const UninitVector<uint32_t> listed =
      listed_by_tile(rects, depth_sorted(rects, s.projections), s);
  const UninitVector<std::array<int16_t, 2>> slot_rows = narrowed_slot_rows(rects, entries, s);
  // Each pair's entry from its Gaussian's alone (its tiles from its pixel rectangle, its first
  // slot in it): one read of scattered memory per pair (two for a rectangle of several columns).
  s.tile_gaussians.resize(s.slot_offsets.back());
  tbb::parallel_for(
      tbb::blocked_range<int>(0, s.tile_count(), 4), [&](const tbb::blocked_range<int>& r) {
        for (int t = r.begin(); t != r.end(); ++t) {
          const int tx = t % s.tiles_x, ty = t / s.tiles_x;
          for (uint32_t k = s.tile_offsets[t]; k < s.tile_offsets[t + 1]; ++k) {
            TileGaussian& entry = s.tile_gaussians[k] = entries[listed[k]];
            const int tx0 = entry.x0 / kTileSize, tx1 = (entry.x1 - 1) / kTileSize + 1;
            entry.slot += uint32_t((ty - entry.y0 / kTileSize) * (tx1 - tx0) + (tx - tx0));
            if (tx1 - tx0 > 1) {
              const std::array<int16_t, 2>& rows = slot_rows[entry.slot];
              entry.y0 = rows[0];
              entry.y1 = rows[1];
            }
          }
        }
      });
}

void bin_gaussians(const GaussianModel& model, const ViewTransform& view,
                   const RenderSettings& settings, RasterState& s) {
  const size_t n = model.size();
  s.projections.resize(n);
  s.values.resize(n * s.channels + kValuePiece);
  std::vector<BlendRect> rects(n);
  // Per Gaussian, what all its tile-list entries share (all but the slot): computed once here
  // rather than once per tile, since a Gaussian is in about three tiles.
  UninitVector<TileGaussian> entries(n);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t g = r.begin(); g != r.end(); ++g) {
          ProjectedGaussian& p = s.projections[g];
          if (!project_gaussian(view, &model.means[3 * g], &model.log_scales[3 * g],
                                &model.quats[4 * g], settings.near, p))
            continue;
          const float o = sigmoid(model.opacity_logits[g]);
          const BlendRect& rect = rects[g] = blend_rect(p, o, s.min_alpha, s.width, s.height);
          if (rect.tiles() == 0) {
            p.radius = 0;
            continue;
          }
          entries[g] = {p.mean2d.x(),
                        p.mean2d.y(),
                        p.conic[0],
                        p.conic[1],
                        p.conic[2],
                        o,
                        std::log(s.min_alpha / std::max(o, 1e-30f)),
                        int16_t(rect.x0),
                        int16_t(rect.y0),
                        int16_t(rect.x1),
                        int16_t(rect.y1),
                        uint32_t(g),
                        0u};
          write_channel_values(model, view, p, g, s);
        }
      });
  sort_tile_lists(rects, entries, s);
}

// Blends tile t front to back (blend_tile) into acc, structure of arrays: channel c of tile pixel
// p at [c * 256 + p], so that adding one entry's values to a row is a 16-lane FMA per channel.
// kChannels > 0 fixes the channel count, so the channel loop unrolls. With `feature_rows` (one flag
// per tile row) the feature channels, the last block, are blended only in the flagged rows.
template <int kChannels>
void forward_tile(const RasterState& s, int t, const float* values, float* acc, TileBlend& out,
                  const uint8_t* feature_rows) {
  const int C = kChannels > 0 ? kChannels : s.channels;
  blend_tile(s, t, out, [&](uint32_t j, int at, const float* w, const RowLanes&) {
    const float* v = values + size_t(j) * C;
    const int row_c = feature_rows && !feature_rows[at / kTileSize] ? s.feature_offset : C;
#pragma GCC unroll 16
    for (int c = 0; c < row_c; ++c) {
      float* __restrict a = acc + c * kTilePixels + at;
      const float vc = v[c];
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
      for (int x = 0; x < kLanes; ++x) a[x] += w[x] * vc;
    }
  });
}

// The image size, tile grid and channel layout of a render (raster_state.hpp).
void set_channel_layout(const GaussianModel& model, const Camera& camera,
                        const RenderSettings& settings, RasterState& s) {
  s.width = camera.width;
  s.height = camera.height;
  s.tiles_x = (s.width + kTileSize - 1) / kTileSize;
  s.tiles_y = (s.height + kTileSize - 1) / kTileSize;
  s.sh_degree =
      settings.sh_degree < 0 ? model.sh_degree : std::min(settings.sh_degree, model.sh_degree);
  s.min_alpha = std::max(0.f, settings.min_alpha);
  auto add_block = [&](bool on, int size, int& offset) {
    if (on) {
      offset = s.channels;
      s.channels += size;
    }
  };
  add_block(settings.rgb, 3, s.rgb_offset);
  add_block(settings.depth, 1, s.depth_offset);
  add_block(settings.normal, 3, s.normal_offset);
  add_block(settings.alpha || (settings.depth && settings.normalize_depth), 1, s.alpha_offset);
  // Features last: the backward pass skips the channels past the last one with a gradient in a
  // tile row, and a feature objective's gradient is sparse (sampled pixels, feature_objective.hpp).
  add_block(settings.features && model.feature_dim > 0, model.feature_dim, s.feature_offset);
  s.background.assign(s.channels, 0.f);
  for (int k = 0; s.rgb_offset >= 0 && k < 3; ++k)
    s.background[s.rgb_offset + k] = settings.background[k];
}

// The tile rows that hold a requested feature pixel, a flag per row at [tile * kTileSize + row];
// empty when every pixel's features are wanted.
std::vector<uint8_t> feature_row_flags(const RasterState& s, const RenderSettings& settings) {
  std::vector<uint8_t> rows;
  if (s.feature_offset < 0 || !settings.feature_pixels) return rows;
  const size_t pixels = size_t(s.width) * s.height;
  rows.assign(size_t(s.tile_count()) * kTileSize, 0);
  for (const uint32_t p : *settings.feature_pixels) {
    if (p >= pixels)
      throw InputError("rasterizer: feature pixel " + std::to_string(p) + " is outside the image");
    const int x = int(p % s.width), y = int(p / s.width);
    rows[size_t((y / kTileSize) * s.tiles_x + x / kTileSize) * kTileSize + y % kTileSize] = 1;
  }
  return rows;
}

// forward_tile with the common channel counts as fixed-size loops (see backward_tile).
void blend_tile_channels(const RasterState& s, int t, const float* values, float* acc,
                         TileBlend& blend, const uint8_t* rows) {
  switch (s.channels) {
    case 3:
      return forward_tile<3>(s, t, values, acc, blend, rows);
    case 7:
      return forward_tile<7>(s, t, values, acc, blend, rows);
    case 8:
      return forward_tile<8>(s, t, values, acc, blend, rows);
    case 16:
      return forward_tile<16>(s, t, values, acc, blend, rows);
    default:
      return forward_tile<0>(s, t, values, acc, blend, rows);
  }
}

// A blended tile's accumulators ([channel][tile pixel], forward_tile) into the output images and
// the state the backward pass reads.
void store_tile(RasterState& s, int t, const float* acc, const TileBlend& blend,
                const RenderSettings& settings, RenderOutput& out) {
  const int D = out.feature_dim;
  const PixelRect tile = tile_pixels(s, t);
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x) {
      const int p = (y - tile.y0) * kTileSize + (x - tile.x0);
      const size_t pix = size_t(y) * s.width + x;
      auto a = [&](int c) { return acc[size_t(c) * kTilePixels + p]; };
      const float T = blend.T[p];
      s.final_transmittance[pix] = T;
      s.contributors[pix] = blend.last[p];
      for (int c = 0; s.rgb_offset >= 0 && c < 3; ++c)
        out.rgb[pix * 3 + c] = a(s.rgb_offset + c) + T * settings.background[c];
      if (s.depth_offset >= 0) {
        float d = a(s.depth_offset);
        if (settings.normalize_depth) {
          const float alpha = a(s.alpha_offset);
          d = alpha >= kMinAlphaForDepth ? d / alpha : 0.f;
        }
        out.depth[pix] = d;
      }
      for (int c = 0; s.normal_offset >= 0 && c < 3; ++c)
        out.normal[pix * 3 + c] = a(s.normal_offset + c);
      for (int f = 0; s.feature_offset >= 0 && f < D; ++f)
        out.features[pix * D + f] = a(s.feature_offset + f);
      if (s.alpha_offset >= 0) s.alpha_sum[pix] = a(s.alpha_offset);
      if (settings.alpha) out.alpha[pix] = a(s.alpha_offset);
    }
}

}  // namespace

RenderOutput render(const GaussianModel& model, const Camera& camera, const Pose& pose,
                    const RenderSettings& settings) {
  check_model(model);
  if (camera.width <= 0 || camera.height <= 0 || camera.width > 32767 || camera.height > 32767 ||
      !(camera.fx > 0) || !(camera.fy > 0))
    throw InputError(
        "rasterizer: camera has no pixels, more than 32767 in a row or column, or a "
        "non-positive focal length (" +
        std::to_string(camera.width) + "x" + std::to_string(camera.height) + ")");
  check_camera(camera, "rasterizer");  // at most kMaxImagePixels: the state below is per pixel
  const ViewTransform view(camera, pose);
  auto state = std::make_shared<RasterState>();
  RasterState& s = *state;
  set_channel_layout(model, camera, settings, s);
  const int D = model.feature_dim;
  bin_gaussians(model, view, settings, s);

  const size_t pixels = size_t(s.width) * s.height;
  RenderOutput out;
  out.width = s.width;
  out.height = s.height;
  out.feature_dim = settings.features ? D : 0;
  if (settings.rgb) out.rgb.assign(pixels * 3, 0.f);
  if (settings.depth) out.depth.assign(pixels, 0.f);
  if (settings.normal) out.normal.assign(pixels * 3, 0.f);
  if (settings.alpha) out.alpha.assign(pixels, 0.f);
  if (settings.features) out.features.resize(pixels * D);  // store_tile writes every pixel
  const std::vector<uint8_t> feature_rows = feature_row_flags(s, settings);
  // Every pixel lies in a tile, and store_tile writes each of them: no fill first (a serial pass
  // taking the page faults on one thread).
  s.final_transmittance.resize(pixels);
  s.contributors.resize(pixels);
  if (s.alpha_offset >= 0) s.alpha_sum.resize(pixels);

  tbb::parallel_for(
      tbb::blocked_range<int>(0, s.tile_count()), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> values, acc(size_t(kTilePixels) * s.channels);
        TileBlend blend;
        for (int t = r.begin(); t != r.end(); ++t) {
          const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
          gather_values(s, list, s.tile_offsets[t + 1] - s.tile_offsets[t], values);
          std::fill(acc.begin(), acc.end(), 0.f);
          const uint8_t* rows =
              feature_rows.empty() ? nullptr : feature_rows.data() + size_t(t) * kTileSize;
          blend_tile_channels(s, t, values.data(), acc.data(), blend, rows);
          store_tile(s, t, acc.data(), blend, settings, out);
        }
      });

  out.radii.resize(model.size());
  for (size_t g = 0; g < model.size(); ++g) out.radii[g] = s.projections[g].radius;
  out.state = std::move(state);
  return out;
}

}  // namespace gslift
