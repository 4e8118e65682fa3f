// Backward pass of the rasterizer (rasterizer.hpp): exact gradients of every rendered channel with
// respect to every GaussianModel parameter, from the state the forward pass kept.
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
#include "nodes/splat/rasterizer_shared.hpp"
#include "nodes/splat/sh.hpp"

namespace gslift {

namespace {

// v sized to n and zeroed, in parallel blocks: the training loop resets the gradients at every
// step (11 MB for the main job's 45k Gaussians), and one thread filling them kept the other idle.
template <class T>
void assign_zeros(std::vector<T>& v, size_t n) {
  v.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, size_t(1) << 16),
                    [&](const tbb::blocked_range<size_t>& r) {
                      std::fill(v.begin() + r.begin(), v.begin() + r.end(), T(0));
                    });
}

}  // namespace

void ModelGrads::reset(const GaussianModel& model) {
  const size_t n = model.size();
  assign_zeros(means, 3 * n);
  assign_zeros(log_scales, 3 * n);
  assign_zeros(quats, 4 * n);
  assign_zeros(opacity_logits, n);
  assign_zeros(sh, n * GaussianModel::sh_coeffs(model.sh_degree) * 3);
  assign_zeros(features, n * model.feature_dim);
  assign_zeros(mean2d_abs, n);
  assign_zeros(visible, n);
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

  // The `width` pixels of an image row from pixel pix, as tile lanes: g[c * kTilePixels + x] =
  // dL/d(channel c) of pixel pix + x, and nonzero[x] = 1 where any of them is nonzero, else 0.
  // Channel by channel over the lanes, in loops that compile to vector code: one pixel at a
  // time (a memset and a call per source per pixel), this was 1/5 of the backward pass.
  template <int kChannels>
  void row(size_t pix, int width, float* g, float* nonzero) const {
    const int C = kChannels > 0 ? kChannels : s_.channels;
    for (int c = 0; c < C; ++c)
      for (int x = 0; x < width; ++x) g[c * kTilePixels + x] = 0.f;
    for (int x = 0; x < width; ++x) nonzero[x] = 0.f;
    auto put = [&](int offset, const std::vector<float>& src, int size) {
      if (offset < 0 || src.empty()) return;
      for (int c = 0; c < size; ++c)
        for (int x = 0; x < width; ++x) {
          const float v = src[(pix + size_t(x)) * size + c];
          g[(offset + c) * kTilePixels + x] += v;
          nonzero[x] = v != 0.f ? 1.f : nonzero[x];
        }
    };
    put(s_.rgb_offset, grads_.rgb, 3);
    put(s_.normal_offset, grads_.normal, 3);
    put(s_.feature_offset, grads_.features, forward_.feature_dim);
    if (settings_.alpha) put(s_.alpha_offset, grads_.alpha, 1);
    if (s_.depth_offset < 0 || grads_.depth.empty()) return;
    float* depth = g + s_.depth_offset * kTilePixels;
    const float* gd = &grads_.depth[pix];
    if (!settings_.normalize_depth) {
      for (int x = 0; x < width; ++x) {
        depth[x] += gd[x];
        nonzero[x] = gd[x] != 0.f ? 1.f : nonzero[x];
      }
      return;
    }
    // D = S / A with S = depth sum, A = alpha sum: dD/dS = 1/A, dD/dA = -D/A.
    float* alpha = g + s_.alpha_offset * kTilePixels;
    const float* a = &s_.alpha_sum[pix];
    const float* D = &forward_.depth[pix];
    for (int x = 0; x < width; ++x) {
      nonzero[x] = gd[x] != 0.f ? 1.f : nonzero[x];
      if (gd[x] != 0.f && a[x] >= kMinAlphaForDepth) {
        depth[x] += gd[x] / a[x];
        alpha[x] -= gd[x] * D[x] / a[x];
      }
    }
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
constexpr int kSlotGeometry = GeometryMoments::kOutputs;

// Per-worker buffers of backward_tile, structure of arrays: channel c of tile pixel p at [c][p].
struct BackwardScratch {
  explicit BackwardScratch(int channels)
      : g(size_t(kTilePixels) * channels), d(size_t(kLanes) * channels) {}
  std::vector<float> values, g, d;
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
  // Per tile row, the channels up to the last one with a nonzero gradient at any of its pixels:
  // the channels past it add exactly 0 to every sum. A feature objective's gradient (the last
  // block, rasterizer_forward.cpp) is nonzero at a few sampled pixels, so most rows skip it.
  int row_channels[kTileSize] = {};
  const int width = tile.x1 - tile.x0;
  for (int y = tile.y0; y < tile.y1; ++y) {
    const int at = (y - tile.y0) * kTileSize;
    const size_t pix = size_t(y) * s.width + size_t(tile.x0);
    alignas(64) float nonzero[kLanes];
    pixel_grads.row<kChannels>(pix, width, g + at, nonzero);
    // A pixel whose gradient is zero gets no contributor: all its lanes are masked out.
    uint32_t row_max = 0;
    for (int x = 0; x < width; ++x) {
      const uint32_t contributors = nonzero[x] != 0.f ? s.contributors[pix + x] : 0u;
      last[at + x] = float(contributors);
      row_max = std::max(row_max, contributors);
      T[at + x] = s.final_transmittance[pix + x];
    }
    row_last[y - tile.y0] = float(row_max);
    tile_last = std::max(tile_last, row_max);
    for (int c = C; c > 0 && row_channels[y - tile.y0] == 0; --c)
      for (int x = 0; x < width; ++x)
        if (last[at + x] > 0.f && g[(c - 1) * kTilePixels + at + x] != 0.f)
          row_channels[y - tile.y0] = c;
    alignas(64) float background[kLanes] = {};  // g . bg
    for (int c = 0; c < C; ++c)
      for (int x = 0; x < width; ++x)
        background[x] += g[c * kTilePixels + at + x] * s.background[c];
    for (int x = 0; x < width; ++x) Q[at + x] = background[x] * T[at + x];
  }
  for (uint32_t j = tile_last; j < count; ++j)
    std::fill_n(&slot_grads[size_t(list[j].slot) * stride], stride, 0.f);
  // The values of the entries that reach a pixel only: behind the tile's last contributor most
  // of a trained scene's list is never read.
  gather_values(s, list, std::min(count, tile_last), scratch.values);
  for (uint32_t j = std::min(count, tile_last); j-- > 0;) {
    const TileGaussian& e = list[j];
    const PixelRect rect = clip(e, tile);
    float* slot = &slot_grads[size_t(e.slot) * stride];
    // Slots lie in Gaussian order, scattered over a buffer of several MB: the next entry's is
    // prefetched for writing while this one is summed.
    if (j > 0) {
      const float* next = &slot_grads[size_t(list[j - 1].slot) * stride];
      __builtin_prefetch(next, 1);
      __builtin_prefetch(next + stride - 1, 1);
    }
    if (rect.y1 <= rect.y0) {  // no row of this tile it can blend in (narrow_rows): sums of 0
      std::fill_n(slot, stride, 0.f);
      continue;
    }
    const float* v = &scratch.values[size_t(j) * C];
    const float jf = float(j);
    // The entry's lane sums: with a fixed channel count, vector values in registers (as arrays
    // they were loaded and stored again in every row, a store-to-load chain per channel); else
    // arrays zeroed as one vector store per channel (a std::fill or a value-initialised struct of
    // this size compiles to `rep stos`, whose start-up cost per entry was 1/20 of the pass).
    LaneVector d_lanes[kChannels > 0 ? kChannels : 1] = {};
    if constexpr (kChannels == 0)
      for (int c = 0; c < C; ++c) store_lanes(d + c * kLanes, LaneVector{});
    GeometryMoments moments;       // of dL/dpower and dL/dopacity over the entry's pixels
    alignas(64) float dx[kLanes];  // the lanes' pixel offsets from the entry's mean
    for (int x = 0; x < kLanes; ++x) dx[x] = e.mx - (float(tile.x0 + x) + 0.5f);
    // The alphas of all the entry's rows first, as in blend_tile: their exp chains overlap.
    alignas(64) float row_gaussian[kTileSize][kLanes], row_alpha[kTileSize][kLanes];
    for (int y = rect.y0; y < rect.y1; ++y)
      if (jf < row_last[y - tile.y0])
        blend_row(e, y, tile.x0, tile.x0 + kLanes, s.min_alpha, row_gaussian[y - rect.y0],
                  row_alpha[y - rect.y0]);
    for (int y = rect.y0; y < rect.y1; ++y) {
      if (jf >= row_last[y - tile.y0]) continue;
      const float dy = e.my - (float(y) + 0.5f);
      const float* gaussian = row_gaussian[y - rect.y0];
      const float* alpha = row_alpha[y - rect.y0];
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
      // gv as one vector value: as an array, GCC stores and reloads it for every channel, a
      // store-to-load chain that took 1/6 of the backward pass; the same operations per lane.
      const int row_c = row_channels[y - tile.y0];
      LaneVector gv_lanes = load_lanes(gv);
      const LaneVector w_lanes = load_lanes(w);
      if constexpr (kChannels > 0) {
#pragma GCC unroll 16
        for (int c = 0; c < kChannels; ++c)
          if (c < row_c) {
            const LaneVector gc = load_lanes(g + c * kTilePixels + at);
            gv_lanes += gc * v[c];
            d_lanes[c] += w_lanes * gc;
          }
      } else {
        for (int c = 0; c < row_c; ++c) {
          const LaneVector gc = load_lanes(g + c * kTilePixels + at);
          float* dc = d + c * kLanes;
          gv_lanes += gc * v[c];
          store_lanes(dc, load_lanes(dc) + w_lanes * gc);
        }
      }
      store_lanes(gv, gv_lanes);
      // alpha = o exp(power), power = -0.5 (A dx^2 + C dy^2) - B dx dy: the power's gradients
      // are linear in the moments (applied per entry below). A clamped alpha is constant, and a
      // masked lane has a = 0, so it adds nothing.
      alignas(64) float d_power[kLanes], d_opacity[kLanes];
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
      for (int x = 0; x < kLanes; ++x) {
        const float d_alpha = gv[x] * Tj[x] - Q[at + x] * inv_keep[x];
        Q[at + x] += w[x] * gv[x];
        const bool free = e.opacity * gaussian[x] <= kMaxAlpha;
        d_power[x] = free ? d_alpha * a[x] : 0.f;
        d_opacity[x] = (free & (a[x] > 0.f)) ? d_alpha * gaussian[x] : 0.f;
      }
      moments.add(dx, dy, d_power, d_opacity);
    }
    // The entry's sums, its slot in order (the moments', then each channel's), in trees of up to
    // kLanes vectors (lane_sums).
    LaneVector geometry[kSlotGeometry];
    moments.vectors(geometry);
    auto lanes_of = [&](int k) {
      if (k < kSlotGeometry) return geometry[k];
      if constexpr (kChannels > 0) return d_lanes[k - kSlotGeometry];
      return load_lanes(d + (k - kSlotGeometry) * kLanes);
    };
    for (int i = 0; i < stride; i += kLanes) {
      const int n = std::min(kLanes, stride - i);
      LaneVector chunk[kLanes];
      for (int k = 0; k < n; ++k) chunk[k] = lanes_of(i + k);
      alignas(64) float sums[kLanes];
      lane_sums(chunk, n, sums);
      if (i == 0) GeometryMoments::finish(e, sums, slot);
      for (int k = std::max(i, kSlotGeometry); k < i + n; ++k) slot[k] = sums[k - i];
    }
  }
}

// The forward pass's state and the accumulator fit this model and camera.
void check_backward_sizes(const GaussianModel& model, const Camera& camera, const RasterState& s,
                          const ModelGrads& accumulate) {
  const size_t n = model.size();
  if (s.projections.size() != n || s.width != camera.width || s.height != camera.height)
    throw InputError("render_backward: the forward pass was rendered for another model or camera");
  const int K = GaussianModel::sh_coeffs(model.sh_degree);
  if (accumulate.means.size() != 3 * n || accumulate.log_scales.size() != 3 * n ||
      accumulate.quats.size() != 4 * n || accumulate.opacity_logits.size() != n ||
      accumulate.sh.size() != n * K * 3 ||
      accumulate.features.size() != n * size_t(model.feature_dim) ||
      accumulate.mean2d_abs.size() != n || accumulate.visible.size() != n)
    throw InputError("render_backward: ModelGrads sizes do not match the model (call reset())");
}

// backward_tile with the common channel counts as loops of fixed length (rgb; rgb + depth +
// normal (+ alpha); 16 features).
void backward_tile_channels(const RasterState& s, int t, const PixelGrads& pixel_grads,
                            float* slot_grads, BackwardScratch& scratch) {
  switch (s.channels) {
    case 3:
      return backward_tile<3>(s, t, pixel_grads, slot_grads, scratch);
    case 7:
      return backward_tile<7>(s, t, pixel_grads, slot_grads, scratch);
    case 8:
      return backward_tile<8>(s, t, pixel_grads, slot_grads, scratch);
    case 16:
      return backward_tile<16>(s, t, pixel_grads, slot_grads, scratch);
    default:
      return backward_tile<0>(s, t, pixel_grads, slot_grads, scratch);
  }
}

// Gaussian gi's colour gradient d_rgb through its SH coefficients and, through the view
// direction, its mean. A clamped (negative) colour channel passes no gradient. Returns the part
// of the mean's gradient that came through the view direction.
Eigen::Vector3f sh_colour_backward(const GaussianModel& model, const ViewTransform& view,
                                   int sh_degree, size_t gi, const float* d_rgb,
                                   ModelGrads& accumulate) {
  const int K = GaussianModel::sh_coeffs(model.sh_degree);
  float basis[kMaxShCoeffs];
  Eigen::Vector3f basis_grad[kMaxShCoeffs];
  float length;
  const Eigen::Vector3f dir = view_direction(view, &model.means[3 * gi], length);
  sh_basis(sh_degree, dir, basis, basis_grad);
  const float* sh = &model.sh[gi * K * 3];
  const Eigen::Vector3f raw = sh_colour(sh, sh_degree, basis);
  Eigen::Vector3f d_colour;
  for (int c = 0; c < 3; ++c) d_colour[c] = raw[c] < 0.f ? 0.f : d_rgb[c];
  Eigen::Vector3f d_dir = Eigen::Vector3f::Zero();
  for (int k = 0; k < GaussianModel::sh_coeffs(sh_degree); ++k) {
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
  return d_mu;
}

}  // namespace

void render_backward(const GaussianModel& model, const Camera& camera, const Pose& pose,
                     const RenderSettings& settings, const RenderOutput& forward,
                     const RenderGrads& grads, ModelGrads& accumulate, PoseGradient* pose_grad) {
  check_model(model);
  if (!forward.state) throw InputError("render_backward: the forward output has no raster state");
  const RasterState& s = *forward.state;
  const size_t n = model.size();
  check_backward_sizes(model, camera, s, accumulate);
  const int D = model.feature_dim;
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
                      for (int t = r.begin(); t != r.end(); ++t)
                        backward_tile_channels(s, t, pixel_grads, slot_grads.data(), scratch);
                    });

  // Per Gaussian, its share of the pose gradient, summed in Gaussian order after the pass.
  std::vector<float> pose_parts(pose_grad ? 6 * n : 0, 0.f);
  // Pass 2, per Gaussian: sum its slots in tile order, then chain through colour and projection.
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
        std::vector<float> sum(stride);
        for (size_t gi = r.begin(); gi != r.end(); ++gi) {
          if (s.slot_offsets[gi] == s.slot_offsets[gi + 1]) continue;
          std::fill(sum.begin(), sum.end(), 0.f);
          for (uint32_t k = s.slot_offsets[gi]; k < s.slot_offsets[gi + 1]; ++k)
            for (int c = 0; c < stride; ++c) sum[c] += slot_grads[size_t(k) * stride + c];
          const float* dv = sum.data() + kSlotGeometry;
          const float* mean = &model.means[3 * gi];

          const float o = sigmoid(model.opacity_logits[gi]);
          accumulate.opacity_logits[gi] += sum[5] * o * (1.f - o);
          float* d_pose = pose_grad ? &pose_parts[6 * gi] : nullptr;
          if (s.rgb_offset >= 0) {
            const Eigen::Vector3f d_dir_mu =
                sh_colour_backward(model, view, s.sh_degree, gi, dv + s.rgb_offset, accumulate);
            // The camera centre moves by -R^T dt under the correction (pose_correction.hpp).
            if (d_pose) Eigen::Map<Eigen::Vector3f>(d_pose + 3) += view.R * d_dir_mu;
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
                                    &accumulate.quats[4 * gi], d_pose);
          // View-space gradient in NDC units for densification (3DGS threshold 2e-4).
          accumulate.mean2d_abs[gi] +=
              std::hypot(sum[0] * 0.5f * s.width, sum[1] * 0.5f * s.height);
          accumulate.visible[gi] += 1;
        }
      });
  if (pose_grad) {
    pose_grad->setZero();
    for (size_t gi = 0; gi < n; ++gi)
      for (int k = 0; k < 6; ++k) (*pose_grad)[k] += pose_parts[6 * gi + k];
  }
}

}  // namespace gslift
