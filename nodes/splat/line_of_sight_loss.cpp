// Vector width of the blending loops it shares with the rasterizer: see rasterizer_forward.cpp.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/line_of_sight_loss.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/ray_depth.hpp"
#include "nodes/splat/tile_list_grads.hpp"

namespace gslift {

namespace {

// Each pixel's cut depth in a tile: depth_factor x its prior depth; a pixel without a prior gets
// a cut of 0, which puts every Gaussian behind it (the near plane is > 0). Returns the pixels
// with a prior.
size_t depth_prior_cut(const cv::Mat1f& prior_depth, const PixelRect& tile, double depth_factor,
                       float* cut) {
  size_t observed = 0;
  for (int p = 0; p < kTilePixels; ++p) {
    const int x = tile.x0 + p % kTileSize, y = tile.y0 + p / kTileSize;
    const float D = x < tile.x1 && y < tile.y1 ? prior_depth(y, x) : 0.f;
    const bool has = D > 0 && std::isfinite(D);
    cut[p] = has ? static_cast<float>(depth_factor * D) : 0.f;
    observed += has;
  }
  return observed;
}

}  // namespace

double opacity_before_prior(const GaussianModel& model, const Camera& camera, const Pose& pose,
                            const cv::Mat1f& prior_depth, const RenderOutput& forward,
                            double depth_factor, double scale, ModelGrads* grads,
                            size_t* observed_pixels, bool ray_depth) {
  if (!forward.state) throw std::invalid_argument("opacity_before_prior: the render has no state");
  const RasterState& s = *forward.state;
  if (s.width != prior_depth.cols || s.height != prior_depth.rows)
    throw std::invalid_argument("opacity_before_prior: the depth prior is not the render's size");
  // Per tile, two passes over its list in the rasterizer's lane layout (raster_state.hpp): front
  // to back, each pixel's transmittance T_p through the Gaussians in front of its cut; then, as
  // dF/da_k = T_p / (1 - a_k) needs the final T_p, the same contributions again for the
  // gradient, summed per list entry into its slot (mean2d, conic, opacity: GeometryMoments).
  constexpr int kPartials = GeometryMoments::kOutputs;
  const int tiles = s.tile_count();
  std::vector<double> tile_loss(tiles, 0.0);
  std::vector<size_t> tile_observed(tiles, 0);  // pixels with a prior: the mean's denominator
  UninitVector<float> slots(grads ? s.tile_gaussians.size() * kPartials : 0);
  // Per tile, given the entries' depths at each pixel (EntryDepth: their centres', or along each
  // pixel's ray).
  with_entry_depths(ray_depth, model, camera, pose, s, [&](const auto& depth) {
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles), [&](const tbb::blocked_range<int>& r) {
      TileBlend front;
      BlendedRows rows;
      alignas(64) float cut[kTilePixels];
      for (int t = r.begin(); t != r.end(); ++t) {
        const PixelRect tile = tile_pixels(s, t);
        tile_observed[t] = depth_prior_cut(prior_depth, tile, depth_factor, cut);
        // Alphas and early stop exactly as the forward pass blends, restricted to the Gaussians in
        // front of each pixel's cut; the rows it blends are kept for the gradient.
        rows.clear();
        blend_tile(
            s, t, front,
            [&](uint32_t j, int at, const float*, const RowLanes& lanes) {
              if (grads) rows.add(j, at, lanes);
            },
            cut, depth);
        double loss = 0;
        for (int p = 0; p < kTilePixels; ++p) loss += 1.0 - front.T[p];  // 0 where none in front
        tile_loss[t] = loss;
        if (!grads) continue;
        // F = 1 - prod (1 - a_k): dF/da_k = T / (1 - a_k); a = o G, G = exp(power); a clamped
        // alpha is constant.
        auto add_row = [&](uint32_t j, const TileGaussian& e, const PixelRect& rect, int y, int at,
                           const RowLanes& lanes, GeometryMoments& moments) {
          const float dy = e.my - (float(y) + 0.5f);
          alignas(64) float dx[kLanes], d_power[kLanes], d_opacity[kLanes];
          const float *alpha = lanes.alpha, *z = lanes.depth;
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
          for (int x = 0; x < kLanes; ++x) {
            const int px = tile.x0 + x;
            // In front of the cut: implied by j < last for centre depths (the lists' order), not
            // for ray depths.
            const bool active = (px >= rect.x0) & (px < rect.x1) & (alpha[x] >= 0.f) &
                                (j < front.last[at + x]) & (z[x] < cut[at + x]) &
                                (alpha[x] < kMaxAlpha);
            const float a = active ? alpha[x] : 0.f;
            const float dF_da = front.T[at + x] / (1.f - a);
            dx[x] = e.mx - (float(px) + 0.5f);
            d_power[x] = active ? dF_da * a : 0.f;
            d_opacity[x] = active ? dF_da * lanes.gaussian[x] : 0.f;
          }
          moments.add(dx, dy, d_power, d_opacity);
        };
        walk_contributions(s, t, front, rows, slots.data(), add_row);
      }
    });
  });
  double loss = 0;
  size_t observed = 0;
  for (int t = 0; t < tiles; ++t) {
    loss += tile_loss[t];
    observed += tile_observed[t];
  }
  if (observed_pixels) *observed_pixels = observed;
  if (observed == 0) return 0.0;
  loss /= static_cast<double>(observed);
  if (!grads) return loss;

  add_slot_grads(model, camera, pose, s, slots.data(), nullptr,
                 static_cast<float>(scale / static_cast<double>(observed)), *grads);
  return loss;
}

double line_of_sight_loss(const GaussianModel& model, const Camera& camera, const Pose& pose,
                          const cv::Mat1f& prior_depth, const RenderOutput& forward,
                          double tolerance, double scale, ModelGrads* grads, bool ray_depth) {
  return opacity_before_prior(model, camera, pose, prior_depth, forward, 1 - tolerance, scale,
                              grads, nullptr, ray_depth);
}

}  // namespace gslift
