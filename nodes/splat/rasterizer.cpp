// The blending loops are written for 16 lanes (raster_state.hpp: kLanes); GCC's default for
// -march=native on AVX-512 machines splits them into two 256-bit halves. One 512-bit register is
// 1.1x faster on the 50k bench; the option only matters where AVX-512 is enabled.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/rasterizer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/sh.hpp"

namespace gslift {

namespace {

void check_size(const char* what, size_t got, size_t expected) {
  if (got != expected)
    throw InputError(std::string("GaussianModel: ") + what + " has " + std::to_string(got) +
                     " values, expected " + std::to_string(expected));
}

void check_model(const GaussianModel& model) {
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

float sigmoid(float x) {
  return 1.f / (1.f + std::exp(-x));
}

// View direction of a Gaussian (camera centre -> mean) and its length.
Eigen::Vector3f view_direction(const ViewTransform& view, const float* mean, float& length) {
  const Eigen::Vector3f d = Eigen::Vector3f(mean[0], mean[1], mean[2]) - view.centre;
  length = std::max(d.norm(), 1e-12f);
  return d / length;
}

// SH colour before the clamp at 0: sum_k Y_k(dir) sh_k + 0.5 (3DGS).
Eigen::Vector3f sh_colour(const float* sh, int degree, const float* basis) {
  Eigen::Vector3f c = Eigen::Vector3f::Constant(0.5f);
  for (int k = 0; k < GaussianModel::sh_coeffs(degree); ++k)
    c += basis[k] * Eigen::Vector3f(sh[3 * k], sh[3 * k + 1], sh[3 * k + 2]);
  return c;
}

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
void bin_gaussians(const GaussianModel& model, const ViewTransform& view,
                   const RenderSettings& settings, RasterState& s) {
  const size_t n = model.size();
  const int K = GaussianModel::sh_coeffs(model.sh_degree);
  const int D = model.feature_dim;
  s.projections.resize(n);
  s.values.assign(n * s.channels, 0.f);
  std::vector<BlendRect> rects(n);
  // Per Gaussian, what all its tile-list entries share (all but the slot): computed once here
  // rather than once per tile, since a Gaussian is in about three tiles.
  UninitVector<TileGaussian> entries(n);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
        float basis[kMaxShCoeffs];
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
          float* v = &s.values[g * s.channels];
          if (s.rgb_offset >= 0) {
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
      });

  // Slots: Gaussian g owns one per tile of its rectangle, row by row. Tile lists: a counting sort
  // of the (tile, Gaussian) pairs by tile, each pair as its 64-bit sort key (depth order, Gaussian
  // index), then a sort of each tile's keys: ties in depth are broken by Gaussian index, so the
  // order never depends on scheduling, and sorting integers is 2x faster than comparing structs.
  const int tiles = s.tile_count();
  s.slot_offsets.assign(n + 1, 0);
  s.tile_offsets.assign(tiles + 1, 0);
  for (size_t g = 0; g < n; ++g) {
    const BlendRect& rect = rects[g];
    if (uint64_t(s.slot_offsets[g]) + rect.tiles() >= std::numeric_limits<uint32_t>::max())
      throw InputError("rasterizer: more than 2^32 Gaussian-tile pairs");
    s.slot_offsets[g + 1] = s.slot_offsets[g] + rect.tiles();
    for (int ty = rect.ty0; ty < rect.ty1; ++ty)
      for (int tx = rect.tx0; tx < rect.tx1; ++tx) ++s.tile_offsets[ty * s.tiles_x + tx + 1];
  }
  for (int t = 0; t < tiles; ++t) s.tile_offsets[t + 1] += s.tile_offsets[t];
  const uint32_t pairs = s.slot_offsets[n];
  UninitVector<uint64_t> keys(pairs);
  std::vector<uint32_t> cursor(s.tile_offsets.begin(), s.tile_offsets.end() - 1);
  for (size_t g = 0; g < n; ++g) {
    const BlendRect& rect = rects[g];
    const uint64_t key = uint64_t(depth_order(s.projections[g].depth)) << 32 | g;
    for (int ty = rect.ty0; ty < rect.ty1; ++ty)
      for (int tx = rect.tx0; tx < rect.tx1; ++tx) keys[cursor[ty * s.tiles_x + tx]++] = key;
  }
  s.tile_gaussians.resize(pairs);
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 4), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t != r.end(); ++t) {
      const int tx = t % s.tiles_x, ty = t / s.tiles_x;
      std::sort(&keys[s.tile_offsets[t]], &keys[s.tile_offsets[t + 1]]);
      for (uint32_t k = s.tile_offsets[t]; k < s.tile_offsets[t + 1]; ++k) {
        const uint32_t g = uint32_t(keys[k]);
        const BlendRect& rect = rects[g];
        TileGaussian& entry = s.tile_gaussians[k] = entries[g];
        entry.slot =
            s.slot_offsets[g] + uint32_t((ty - rect.ty0) * (rect.tx1 - rect.tx0) + (tx - rect.tx0));
      }
    }
  });
}

// Copies a tile's per-Gaussian values into a contiguous buffer (cache-friendly blending).
void gather_values(const RasterState& s, const TileGaussian* list, uint32_t count,
                   std::vector<float>& out) {
  out.resize(size_t(count) * s.channels);
  for (uint32_t j = 0; j < count; ++j)
    std::copy_n(&s.values[size_t(list[j].id) * s.channels], s.channels,
                &out[size_t(j) * s.channels]);
}

// Blends tile t front to back (blend_tile) into acc, structure of arrays: channel c of tile pixel
// p at [c * 256 + p], so that adding one entry's values to a row is a 16-lane FMA per channel.
// kChannels > 0 fixes the channel count, so the channel loop unrolls.
template <int kChannels>
void forward_tile(const RasterState& s, int t, const float* values, float* acc, TileBlend& out) {
  const int C = kChannels > 0 ? kChannels : s.channels;
  blend_tile(s, t, out, [&](uint32_t j, int at, const float* w) {
    const float* v = values + size_t(j) * C;
#pragma GCC unroll 16
    for (int c = 0; c < C; ++c) {
      float* __restrict a = acc + c * kTilePixels + at;
      const float vc = v[c];
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
      for (int x = 0; x < kLanes; ++x) a[x] += w[x] * vc;
    }
  });
}

constexpr float kMinAlphaForDepth = 1e-6f;  // normalised depth is 0 below this accumulated alpha

}  // namespace

void ModelGrads::reset(const GaussianModel& model) {
  const size_t n = model.size();
  means.assign(3 * n, 0.f);
  log_scales.assign(3 * n, 0.f);
  quats.assign(4 * n, 0.f);
  opacity_logits.assign(n, 0.f);
  sh.assign(n * GaussianModel::sh_coeffs(model.sh_degree) * 3, 0.f);
  features.assign(n * model.feature_dim, 0.f);
  mean2d_abs.assign(n, 0.f);
  visible.assign(n, 0);
}

RenderOutput render(const GaussianModel& model, const Camera& camera, const Pose& pose,
                    const RenderSettings& settings) {
  check_model(model);
  if (camera.width <= 0 || camera.height <= 0 || camera.width > 32767 || camera.height > 32767 ||
      !(camera.fx > 0) || !(camera.fy > 0))
    throw InputError(
        "rasterizer: camera has no pixels, more than 32767 in a row or column, or a "
        "non-positive focal length (" +
        std::to_string(camera.width) + "x" + std::to_string(camera.height) + ")");
  const ViewTransform view(camera, pose);
  auto state = std::make_shared<RasterState>();
  RasterState& s = *state;
  s.width = camera.width;
  s.height = camera.height;
  s.tiles_x = (s.width + kTileSize - 1) / kTileSize;
  s.tiles_y = (s.height + kTileSize - 1) / kTileSize;
  s.sh_degree =
      settings.sh_degree < 0 ? model.sh_degree : std::min(settings.sh_degree, model.sh_degree);
  s.min_alpha = std::max(0.f, settings.min_alpha);
  const int D = model.feature_dim;
  auto add_block = [&](bool on, int size, int& offset) {
    if (on) {
      offset = s.channels;
      s.channels += size;
    }
  };
  add_block(settings.rgb, 3, s.rgb_offset);
  add_block(settings.depth, 1, s.depth_offset);
  add_block(settings.normal, 3, s.normal_offset);
  add_block(settings.features && D > 0, D, s.feature_offset);
  add_block(settings.alpha || (settings.depth && settings.normalize_depth), 1, s.alpha_offset);
  s.background.assign(s.channels, 0.f);
  for (int k = 0; s.rgb_offset >= 0 && k < 3; ++k)
    s.background[s.rgb_offset + k] = settings.background[k];

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
  if (settings.features) out.features.assign(pixels * D, 0.f);
  s.final_transmittance.assign(pixels, 1.f);
  s.contributors.assign(pixels, 0);
  if (s.alpha_offset >= 0) s.alpha_sum.assign(pixels, 0.f);

  tbb::parallel_for(
      tbb::blocked_range<int>(0, s.tile_count()), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> values, acc(size_t(kTilePixels) * s.channels);
        TileBlend blend;
        for (int t = r.begin(); t != r.end(); ++t) {
          const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
          gather_values(s, list, s.tile_offsets[t + 1] - s.tile_offsets[t], values);
          std::fill(acc.begin(), acc.end(), 0.f);
          // The common channel counts get fixed-size loops (see backward_tile).
          switch (s.channels) {
            case 3:
              forward_tile<3>(s, t, values.data(), acc.data(), blend);
              break;
            case 7:
              forward_tile<7>(s, t, values.data(), acc.data(), blend);
              break;
            case 8:
              forward_tile<8>(s, t, values.data(), acc.data(), blend);
              break;
            case 16:
              forward_tile<16>(s, t, values.data(), acc.data(), blend);
              break;
            default:
              forward_tile<0>(s, t, values.data(), acc.data(), blend);
              break;
          }
          const PixelRect tile = tile_pixels(s, t);
          for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
              const int p = (y - tile.y0) * kTileSize + (x - tile.x0);
              const size_t pix = size_t(y) * s.width + x;
              // acc is [channel][tile pixel] (forward_tile).
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
      });

  out.radii.resize(model.size());
  for (size_t g = 0; g < model.size(); ++g) out.radii[g] = s.projections[g].radius;
  out.state = std::move(state);
  return out;
}

namespace {

// dL/d(channel block) per pixel in the state's channel layout; the normalised depth's quotient
// rule (D = depth_sum / alpha_sum) is folded into the depth and alpha channels.
class PixelGrads {
 public:
  PixelGrads(const RasterState& s, const RenderSettings& settings, const RenderOutput& forward,
             const RenderGrads& grads)
      : s_(s), settings_(settings), forward_(forward), grads_(grads) {
    const size_t pixels = size_t(s.width) * s.height;
    check("rgb", grads.rgb, s.rgb_offset >= 0, pixels * 3);
    check("depth", grads.depth, s.depth_offset >= 0, pixels);
    check("normal", grads.normal, s.normal_offset >= 0, pixels * 3);
    check("alpha", grads.alpha, settings.alpha, pixels);
    check("features", grads.features, s.feature_offset >= 0, pixels * forward.feature_dim);
  }

  // Fills g (channels) for pixel pix; returns false when every entry is zero.
  bool at(size_t pix, float* g) const {
    std::fill(g, g + s_.channels, 0.f);
    bool any = false;
    auto put = [&](int offset, const std::vector<float>& src, int size) {
      if (offset < 0 || src.empty()) return;
      for (int c = 0; c < size; ++c) {
        g[offset + c] += src[pix * size + c];
        any |= src[pix * size + c] != 0.f;
      }
    };
    put(s_.rgb_offset, grads_.rgb, 3);
    put(s_.normal_offset, grads_.normal, 3);
    put(s_.feature_offset, grads_.features, forward_.feature_dim);
    if (settings_.alpha) put(s_.alpha_offset, grads_.alpha, 1);
    if (s_.depth_offset >= 0 && !grads_.depth.empty() && grads_.depth[pix] != 0.f) {
      any = true;
      const float gd = grads_.depth[pix];
      if (!settings_.normalize_depth) {
        g[s_.depth_offset] += gd;
      } else {
        // D = S / A with S = depth sum, A = alpha sum: dD/dS = 1/A, dD/dA = -D/A.
        const float a = s_.alpha_sum[pix];
        if (a >= kMinAlphaForDepth) {
          g[s_.depth_offset] += gd / a;
          g[s_.alpha_offset] -= gd * forward_.depth[pix] / a;
        }
      }
    }
    return any;
  }

 private:
  static void check(const char* name, const std::vector<float>& g, bool rendered, size_t size) {
    if (g.empty()) return;
    if (!rendered)
      throw InputError(std::string("render_backward: gradient given for ") + name +
                       ", which the forward pass did not render");
    if (g.size() != size)
      throw InputError(std::string("render_backward: ") + name + " gradient has " +
                       std::to_string(g.size()) + " values, expected " + std::to_string(size));
  }

  const RasterState& s_;
  const RenderSettings& settings_;
  const RenderOutput& forward_;
  const RenderGrads& grads_;
};

// Per (Gaussian, tile) slot: dL/d mean2d (2), conic (3), opacity (1), then the channel values.
constexpr int kSlotGeometry = 6;

// Sum of kLanes lanes, pairwise in a fixed order (vectorisable, and the same at any thread count).
inline float lane_sum(float* a) {
  for (int h = kLanes / 2; h > 0; h /= 2)
    for (int i = 0; i < h; ++i) a[i] += a[i + h];
  return a[0];
}

// Per-worker buffers of backward_tile, structure of arrays: channel c of tile pixel p at [c][p].
struct BackwardScratch {
  explicit BackwardScratch(int channels)
      : g(size_t(kTilePixels) * channels), d(size_t(kLanes) * channels), pixel(channels) {}
  std::vector<float> values, g, d, pixel;
};

// Backward pass of tile t, back to front (3DGS backward): entry by entry in reverse depth order,
// so every pixel still sees its contributions back to front. An entry is processed one tile row
// at a time, the row's pixels as the lanes of branch-free loops (see kLanes; lanes outside the
// entry's rectangle, skipped, or past the pixel's last contributor get alpha 0 and add nothing),
// with the pixel state in structure-of-arrays layout. The per-entry sums are kLanes lane
// accumulators reduced once per entry in a fixed order. Each entry's gradient goes to its own
// slot, so no two tiles write the same memory. kChannels > 0 fixes the channel count.
//
// With pixel colour P = sum_i v_i alpha_i T_i + T_N bg and g = dL/dP, 3DGS keeps per channel what
// the entries behind j add, S_j = sum_{i>j} v_i w_i + T_N bg, for
// dL/dalpha_j = sum_c g_c (v_jc T_j - S_jc / (1 - alpha_j)). Only the dot product Q_j = g . S_j
// enters, and it updates as Q_{j-1} = Q_j + w_j (g . v_j): one value per pixel instead of C, and
// g . v_j is needed for the first term anyway, so the channel loop is two FMAs per lane.
template <int kChannels>
void backward_tile(const RasterState& s, int t, const PixelGrads& pixel_grads, float* slot_grads,
                   BackwardScratch& scratch) {
  const int C = kChannels > 0 ? kChannels : s.channels;
  const int stride = kSlotGeometry + C;
  const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
  const uint32_t count = s.tile_offsets[t + 1] - s.tile_offsets[t];
  if (count == 0) return;
  gather_values(s, list, count, scratch.values);
  float* g = scratch.g.data();  // dL/d(pixel channel), [c][p]
  float* d = scratch.d.data();  // lane accumulators of dL/d(entry value), [c][lane]
  alignas(64) float T[kTilePixels];
  alignas(64) float Q[kTilePixels];     // g . (what the entries behind the current one add)
  alignas(64) float last[kTilePixels];  // last contributor + 1, as float: compared in the lanes
  const PixelRect tile = tile_pixels(s, t);
  for (int p = 0; p < kTilePixels; ++p) {
    T[p] = 1.f;
    Q[p] = 0.f;
    last[p] = 0.f;
    for (int c = 0; c < C; ++c) g[c * kTilePixels + p] = 0.f;
  }
  // The entries at or past a row's last contributor add nothing to it (all lanes masked, so T
  // and Q stay and every sum gains 0), and those past the tile's last contributor nothing at all:
  // behind opaque surfaces that is most of a trained scene's tile list. Skipping them is exact.
  float row_last[kTileSize] = {};
  uint32_t tile_last = 0;
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x) {
      const int p = (y - tile.y0) * kTileSize + (x - tile.x0);
      const size_t pix = size_t(y) * s.width + x;
      uint32_t contributors = s.contributors[pix];
      if (contributors > 0 && !pixel_grads.at(pix, scratch.pixel.data())) contributors = 0;
      last[p] = float(contributors);
      row_last[y - tile.y0] = std::max(row_last[y - tile.y0], last[p]);
      tile_last = std::max(tile_last, contributors);
      T[p] = s.final_transmittance[pix];
      float background = 0.f;  // g . bg
      for (int c = 0; c < C; ++c) {
        g[c * kTilePixels + p] = scratch.pixel[c];
        background += scratch.pixel[c] * s.background[c];
      }
      Q[p] = background * T[p];
    }
  for (uint32_t j = tile_last; j < count; ++j)
    std::fill_n(&slot_grads[size_t(list[j].slot) * stride], stride, 0.f);
  for (uint32_t j = std::min(count, tile_last); j-- > 0;) {
    const TileGaussian& e = list[j];
    const PixelRect rect = clip(e, tile);
    const float* v = &scratch.values[size_t(j) * C];
    const float jf = float(j);
    std::fill(d, d + size_t(C) * kLanes, 0.f);
    // Lane accumulators of the moments of dL/dpower over the entry's pixels, d = mean2d - pixel:
    // sum p dx, sum p dy, sum p dx^2, sum p dx dy, sum p dy^2 (p = dL/dpower), and of dL/dopacity.
    alignas(64) float m_x[kLanes] = {}, m_y[kLanes] = {}, m_xx[kLanes] = {}, m_xy[kLanes] = {},
                      m_yy[kLanes] = {}, d_opacity[kLanes] = {};
    for (int y = rect.y0; y < rect.y1; ++y) {
      if (jf >= row_last[y - tile.y0]) continue;
      const float dy = e.my - (float(y) + 0.5f);
      alignas(64) float gaussian[kLanes], alpha[kLanes];
      blend_row(e, y, tile.x0, tile.x0 + kLanes, s.min_alpha, gaussian, alpha);
      const int at = (y - tile.y0) * kTileSize;
      // Three passes over the lanes, each a loop without branches that compiles to vector code:
      // transmittance, then the channels one by one, then dL/dalpha and the geometry partials.
      alignas(64) float a[kLanes], inv_keep[kLanes], Tj[kLanes], w[kLanes], gv[kLanes];
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
      for (int x = 0; x < kLanes; ++x) {
        const int px = tile.x0 + x;
        const bool active =
            (px >= rect.x0) & (px < rect.x1) & (alpha[x] >= 0.f) & (jf < last[at + x]);
        a[x] = active ? alpha[x] : 0.f;
        inv_keep[x] = 1.f / (1.f - a[x]);
        Tj[x] = T[at + x] * inv_keep[x];  // transmittance in front of entry j
        T[at + x] = Tj[x];
        w[x] = a[x] * Tj[x];
        gv[x] = 0.f;
      }
#pragma GCC unroll 16  // gv stays in a register across the channels
      for (int c = 0; c < C; ++c) {
        const float* __restrict gc = g + c * kTilePixels + at;
        float* __restrict dc = d + c * kLanes;
        const float vc = v[c];
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
        for (int x = 0; x < kLanes; ++x) {
          gv[x] += gc[x] * vc;
          dc[x] += w[x] * gc[x];
        }
      }
      // alpha = o exp(power), power = -0.5 (A dx^2 + C dy^2) - B dx dy: the power's gradients
      // are linear in the moments (applied per entry below). A clamped alpha is constant, and a
      // masked lane has a = 0, so it adds nothing.
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
      for (int x = 0; x < kLanes; ++x) {
        const float d_alpha = gv[x] * Tj[x] - Q[at + x] * inv_keep[x];
        Q[at + x] += w[x] * gv[x];
        const bool free = e.opacity * gaussian[x] <= kMaxAlpha;
        const float d_power = free ? d_alpha * a[x] : 0.f;
        const float dx = e.mx - (float(tile.x0 + x) + 0.5f);
        const float p_dx = d_power * dx;
        m_x[x] += p_dx;
        m_y[x] += d_power * dy;
        m_xx[x] += p_dx * dx;
        m_xy[x] += p_dx * dy;
        m_yy[x] += d_power * (dy * dy);
        d_opacity[x] += free & (a[x] > 0.f) ? d_alpha * gaussian[x] : 0.f;
      }
    }
    float* slot = &slot_grads[size_t(e.slot) * stride];
    const float sx = lane_sum(m_x), sy = lane_sum(m_y);
    slot[0] = -(e.A * sx + e.B * sy);  // dL/dmean2d = sum p dpower/dd
    slot[1] = -(e.B * sx + e.C * sy);
    slot[2] = -0.5f * lane_sum(m_xx);  // dL/dA, dL/dB, dL/dC
    slot[3] = -lane_sum(m_xy);
    slot[4] = -0.5f * lane_sum(m_yy);
    slot[5] = lane_sum(d_opacity);
    for (int c = 0; c < C; ++c) slot[kSlotGeometry + c] = lane_sum(d + c * kLanes);
  }
}

}  // namespace

void render_backward(const GaussianModel& model, const Camera& camera, const Pose& pose,
                     const RenderSettings& settings, const RenderOutput& forward,
                     const RenderGrads& grads, ModelGrads& accumulate) {
  check_model(model);
  if (!forward.state) throw InputError("render_backward: the forward output has no raster state");
  const RasterState& s = *forward.state;
  const size_t n = model.size();
  if (s.projections.size() != n || s.width != camera.width || s.height != camera.height)
    throw InputError("render_backward: the forward pass was rendered for another model or camera");
  const int K = GaussianModel::sh_coeffs(model.sh_degree);
  const int D = model.feature_dim;
  if (accumulate.means.size() != 3 * n || accumulate.log_scales.size() != 3 * n ||
      accumulate.quats.size() != 4 * n || accumulate.opacity_logits.size() != n ||
      accumulate.sh.size() != n * K * 3 || accumulate.features.size() != n * size_t(D) ||
      accumulate.mean2d_abs.size() != n || accumulate.visible.size() != n)
    throw InputError("render_backward: ModelGrads sizes do not match the model (call reset())");
  const PixelGrads pixel_grads(s, settings, forward, grads);
  const ViewTransform view(camera, pose);

  // Pass 1, per tile, back to front (3DGS backward): see backward_tile.
  const int stride = kSlotGeometry + s.channels;
  // Every slot is written by its tile, so the buffer is not zeroed first (a serial 7 MB pass at
  // 50k Gaussians).
  UninitVector<float> slot_grads(size_t(s.slot_offsets[n]) * stride);
  tbb::parallel_for(tbb::blocked_range<int>(0, s.tile_count()),
                    [&](const tbb::blocked_range<int>& r) {
                      BackwardScratch scratch(s.channels);
                      for (int t = r.begin(); t != r.end(); ++t) {
                        // The common channel counts get loops of fixed length (rgb; rgb + depth +
                        // normal (+ alpha); 16 features).
                        switch (s.channels) {
                          case 3:
                            backward_tile<3>(s, t, pixel_grads, slot_grads.data(), scratch);
                            break;
                          case 7:
                            backward_tile<7>(s, t, pixel_grads, slot_grads.data(), scratch);
                            break;
                          case 8:
                            backward_tile<8>(s, t, pixel_grads, slot_grads.data(), scratch);
                            break;
                          case 16:
                            backward_tile<16>(s, t, pixel_grads, slot_grads.data(), scratch);
                            break;
                          default:
                            backward_tile<0>(s, t, pixel_grads, slot_grads.data(), scratch);
                            break;
                        }
                      }
                    });

  // Pass 2, per Gaussian: sum its slots in tile order, then chain through colour and projection.
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
        std::vector<float> sum(stride);
        float basis[kMaxShCoeffs];
        Eigen::Vector3f basis_grad[kMaxShCoeffs];
        for (size_t gi = r.begin(); gi != r.end(); ++gi) {
          if (s.slot_offsets[gi] == s.slot_offsets[gi + 1]) continue;
          std::fill(sum.begin(), sum.end(), 0.f);
          for (uint32_t k = s.slot_offsets[gi]; k < s.slot_offsets[gi + 1]; ++k)
            for (int c = 0; c < stride; ++c) sum[c] += slot_grads[size_t(k) * stride + c];
          const float* dv = sum.data() + kSlotGeometry;
          const float* mean = &model.means[3 * gi];

          const float o = sigmoid(model.opacity_logits[gi]);
          accumulate.opacity_logits[gi] += sum[5] * o * (1.f - o);
          if (s.rgb_offset >= 0) {
            float length;
            const Eigen::Vector3f dir = view_direction(view, mean, length);
            sh_basis(s.sh_degree, dir, basis, basis_grad);
            const float* sh = &model.sh[gi * K * 3];
            const Eigen::Vector3f raw = sh_colour(sh, s.sh_degree, basis);
            Eigen::Vector3f d_colour;
            for (int c = 0; c < 3; ++c) d_colour[c] = raw[c] < 0.f ? 0.f : dv[s.rgb_offset + c];
            Eigen::Vector3f d_dir = Eigen::Vector3f::Zero();
            for (int k = 0; k < GaussianModel::sh_coeffs(s.sh_degree); ++k) {
              float along = 0.f;
              for (int c = 0; c < 3; ++c) {
                accumulate.sh[(gi * K + k) * 3 + c] += basis[k] * d_colour[c];
                along += sh[3 * k + c] * d_colour[c];
              }
              d_dir += along * basis_grad[k];
            }
            // dir = (mu - centre) / |mu - centre|.
            const Eigen::Vector3f d_mu = (d_dir - dir * dir.dot(d_dir)) / length;
            for (int k = 0; k < 3; ++k) accumulate.means[3 * gi + k] += d_mu[k];
          }
          for (int f = 0; s.feature_offset >= 0 && f < D; ++f)
            accumulate.features[gi * D + f] += dv[s.feature_offset + f];

          ProjectionGrads pg;
          pg.mean2d = Eigen::Vector2f(sum[0], sum[1]);
          pg.conic = Eigen::Vector3f(sum[2], sum[3], sum[4]);
          if (s.depth_offset >= 0) pg.depth = dv[s.depth_offset];
          if (s.normal_offset >= 0)
            pg.normal = Eigen::Vector3f(dv[s.normal_offset], dv[s.normal_offset + 1],
                                        dv[s.normal_offset + 2]);
          project_gaussian_backward(view, mean, &model.log_scales[3 * gi], &model.quats[4 * gi], pg,
                                    &accumulate.means[3 * gi], &accumulate.log_scales[3 * gi],
                                    &accumulate.quats[4 * gi]);
          // View-space gradient in NDC units for densification (3DGS threshold 2e-4).
          accumulate.mean2d_abs[gi] +=
              std::hypot(sum[0] * 0.5f * s.width, sum[1] * 0.5f * s.height);
          accumulate.visible[gi] += 1;
        }
      });
}

}  // namespace gslift
