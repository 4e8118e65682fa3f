// Vector width of the blending loops it shares with the rasterizer: see rasterizer_forward.cpp.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/depth_distortion_loss.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/tile_list_grads.hpp"

namespace gslift {

double depth_distortion_loss(const GaussianModel& model, const Camera& camera, const Pose& pose,
                             const RenderOutput& forward, double scale, ModelGrads* grads) {
  if (!forward.state) throw std::invalid_argument("depth_distortion_loss: the render has no state");
  const RasterState& s = *forward.state;
  std::vector<float> log_depth(s.projections.size(), 0.f);
  for (size_t i = 0; i < log_depth.size(); ++i)
    if (s.projections[i].depth > 0) log_depth[i] = std::log(s.projections[i].depth);
  // Per tile, the forward blend accumulates each pixel's A (sum w), U (sum w u) and L front to
  // back. The gradient pass walks the lists again with the totals known:
  //   dL/dw_k = 2 g_k,  g_k = sum_j w_j |u_k - u_j| = u_k (2 A_<k - A) + U - 2 U_<k,
  //   dL/da_k = 2 (g_k T_k - sum_{i>k} g_i w_i / (1 - a_k)),  sum_{i>k} g_i w_i = L - sum_{i<=k},
  //   dL/du_k = 2 w_k (A_<k - A_>k),
  // summed per list entry into its slot (mean2d, conic, opacity: GeometryMoments; depth apart).
  constexpr int kPartials = GeometryMoments::kOutputs;
  const int tiles = s.tile_count();
  std::vector<double> tile_loss(tiles, 0.0);
  UninitVector<float> slots(grads ? s.tile_gaussians.size() * kPartials : 0);
  UninitVector<float> depth_slots(grads ? s.tile_gaussians.size() : 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles), [&](const tbb::blocked_range<int>& r) {
    TileBlend front;
    alignas(64) float A[kTilePixels], U[kTilePixels], L[kTilePixels];
    alignas(64) float du[kLanes];
    for (int t = r.begin(); t != r.end(); ++t) {
      const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
      const PixelRect tile = tile_pixels(s, t);
      std::fill_n(A, kTilePixels, 0.f);
      std::fill_n(U, kTilePixels, 0.f);
      std::fill_n(L, kTilePixels, 0.f);
      blend_tile(s, t, front, [&](uint32_t j, int at, const float* w) {
        const float u = log_depth[list[j].id];
        for (int x = 0; x < kLanes; ++x) {
          L[at + x] += 2.f * w[x] * (u * A[at + x] - U[at + x]);
          A[at + x] += w[x];
          U[at + x] += w[x] * u;
        }
      });
      double loss = 0;
      for (int p = 0; p < kTilePixels; ++p) loss += L[p];
      tile_loss[t] = loss;
      if (!grads) continue;
      // Running per pixel: transmittance, the sums in front, and sum_{i<=k} g_i w_i.
      alignas(64) float T[kTilePixels], A_front[kTilePixels], U_front[kTilePixels], G[kTilePixels];
      std::fill_n(T, kTilePixels, 1.f);
      std::fill_n(A_front, kTilePixels, 0.f);
      std::fill_n(U_front, kTilePixels, 0.f);
      std::fill_n(G, kTilePixels, 0.f);
      std::fill_n(du, kLanes, 0.f);
      walk_contributions(
          s, t, front, slots.data(),
          [&](uint32_t j, const TileGaussian& e, const PixelRect& rect, int y, int at,
              const float* gaussian, const float* alpha, GeometryMoments& moments) {
            const float u = log_depth[e.id];
            const float dy = e.my - (float(y) + 0.5f);
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
            for (int x = 0; x < kLanes; ++x) {
              const int p = at + x, px = tile.x0 + x;
              const bool live =
                  (px >= rect.x0) & (px < rect.x1) & (alpha[x] >= 0.f) & (j < front.last[p]);
              const float a = live ? alpha[x] : 0.f;
              const float w = a * T[p];
              const float g = u * (2.f * A_front[p] - A[p]) + U[p] - 2.f * U_front[p];
              const float g_upto = G[p] + g * w;
              const float dL_da = live & (alpha[x] < kMaxAlpha)
                                      ? 2.f * (g * T[p] - (L[p] - g_upto) / (1.f - a))
                                      : 0.f;
              du[x] += 2.f * w * (2.f * A_front[p] + w - A[p]);
              const float dx = e.mx - (float(px) + 0.5f);
              moments.add(x, dx, dy, dL_da * a, dL_da * gaussian[x]);
              G[p] = g_upto;
              A_front[p] += w;
              U_front[p] += w * u;
              T[p] *= 1.f - a;
            }
          },
          [&](uint32_t, const TileGaussian& e) {  // du/dz = 1/z; 0 where it drew nothing
            depth_slots[e.slot] = lane_sum(du) / s.projections[e.id].depth;
            std::fill_n(du, kLanes, 0.f);
          });
    }
  });
  double loss = 0;
  for (int t = 0; t < tiles; ++t) loss += tile_loss[t];
  const double pixels = static_cast<double>(s.width) * s.height;
  if (pixels == 0) return 0.0;
  loss /= pixels;
  if (!grads) return loss;

  add_slot_grads(model, camera, pose, s, slots.data(), depth_slots.data(),
                 static_cast<float>(scale / pixels), *grads);
  return loss;
}

}  // namespace gslift
