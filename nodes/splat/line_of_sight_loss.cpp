#include "nodes/splat/line_of_sight_loss.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <tbb/parallel_for.h>

#include "nodes/splat/projection.hpp"
#include "nodes/splat/raster_state.hpp"

namespace gslift {

namespace {

// One (pixel, Gaussian in front of the pixel's prior) pair's share of dL: d/d(mean2d x, y), d/d
// conic (A, B, C), d/d opacity (not its logit).
struct Partial {
  uint32_t id;
  uint8_t term;  // 0: the front term, 1: the behind term (each scaled by its own weight)
  float d[6];
};

}  // namespace

LineOfSightLoss line_of_sight_loss(const GaussianModel& model, const Camera& camera,
                                   const Pose& pose, const cv::Mat1f& prior_depth,
                                   const RenderOutput& forward, double tolerance,
                                   double front_scale, double behind_scale, ModelGrads* grads) {
  if (!forward.state) throw std::invalid_argument("line_of_sight_loss: the render has no state");
  const RasterState& s = *forward.state;
  if (s.width != prior_depth.cols || s.height != prior_depth.rows)
    throw std::invalid_argument("line_of_sight_loss: the depth prior is not the render's size");
  size_t observed = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const float d = prior_depth(y, x);
      observed += d > 0 && std::isfinite(d);
    }
  if (observed == 0) return {};
  const bool behind_term = behind_scale > 0;

  const int tiles = s.tile_count();
  std::vector<double> tile_front(tiles, 0.0), tile_behind(tiles, 0.0);
  std::vector<std::vector<Partial>> tile_partials(tiles);
  tbb::parallel_for(0, tiles, [&](int t) {
    // A blended Gaussian of the pixel, in front of the surface (F), on it (M) or behind it (B).
    enum Where : uint8_t { kFront, kOn, kBehind };
    struct Blended {
      uint32_t id;
      float a, G, dx, dy;
      const TileGaussian* g;
      Where where;
    };
    std::vector<Blended> blended;
    const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
    const uint32_t count = s.tile_offsets[t + 1] - s.tile_offsets[t];
    const int tx = t % s.tiles_x, ty = t / s.tiles_x;
    for (int y = ty * kTileSize; y < std::min(s.height, (ty + 1) * kTileSize); ++y)
      for (int x = tx * kTileSize; x < std::min(s.width, (tx + 1) * kTileSize); ++x) {
        const float D = prior_depth(y, x);
        if (!(D > 0) || !std::isfinite(D)) continue;
        const float near = static_cast<float>((1 - tolerance) * D);
        const float far = static_cast<float>((1 + tolerance) * D);
        // The list is in blending order, front to back: the Gaussians in front are a prefix, the
        // ones behind a suffix. Alphas exactly as the forward pass blends them (raster_state.hpp
        // blend_row). T_front: transmittance past F, T_surface: past F and M, T: past all.
        blended.clear();
        double T = 1, T_front = 1, T_surface = 1;
        for (uint32_t j = 0; j < count; ++j) {
          const TileGaussian& g = list[j];
          const float z = s.projections[g.id].depth;
          const Where where = z < near ? kFront : z <= far ? kOn : kBehind;
          if (where != kFront && !behind_term) break;
          if (x < g.x0 || x >= g.x1 || y < g.y0 || y >= g.y1) continue;
          const float dx = g.mx - (float(x) + 0.5f), dy = g.my - (float(y) + 0.5f);
          const float power = (-0.5f * g.C * dy * dy - 0.5f * g.A * dx * dx) - g.B * dy * dx;
          if (power > 0.f || power < g.power_min) continue;
          const float G = blend_exp(power);
          const float a = std::min(kMaxAlpha, g.opacity * G);
          if (a < s.min_alpha) continue;
          if (T * (1.0 - a) < kMinTransmittance) break;  // where the forward pass stops
          blended.push_back({g.id, a, G, dx, dy, &g, where});
          T *= 1.0 - a;
          if (where == kFront) T_front = T;
          if (where != kBehind) T_surface = T;
        }
        // F = 1 - T_front: dF/da_k = T_front / (1 - a_k) for k in front.
        // W = T_surface - T (the weight drawn behind): dW/da_k = -W / (1 - a_k) for k in front of
        // or on the surface, T / (1 - a_k) for k behind it.
        const double W = T_surface - T;
        tile_front[t] += 1.0 - T_front;
        tile_behind[t] += W;
        if (!grads) continue;
        const auto push = [&](const Blended& b, float dL_da, uint8_t term) {
          const TileGaussian& g = *b.g;
          const float d_power = dL_da * b.a;
          tile_partials[t].push_back(
              {b.id,
               term,
               {-d_power * (g.A * b.dx + g.B * b.dy), -d_power * (g.C * b.dy + g.B * b.dx),
                -0.5f * d_power * b.dx * b.dx, -d_power * b.dx * b.dy,
                -0.5f * d_power * b.dy * b.dy, dL_da * b.G}});
        };
        for (const Blended& b : blended) {
          if (b.a >= kMaxAlpha) continue;  // clamped: constant
          if (b.where == kFront) push(b, static_cast<float>(T_front / (1.0 - b.a)), 0);
          if (behind_term && W > 0)
            push(b, static_cast<float>((b.where == kBehind ? T : -W) / (1.0 - b.a)), 1);
        }
      }
  });
  LineOfSightLoss loss;
  for (int t = 0; t < tiles; ++t) loss.front += tile_front[t], loss.behind += tile_behind[t];
  loss.front /= static_cast<double>(observed);
  loss.behind /= static_cast<double>(observed);
  if (!grads) return loss;
  // Per Gaussian, the screen-space partials summed in tile order, then through the projection.
  const size_t n = model.size();
  std::vector<float> sums(n * 6, 0.f);
  std::vector<char> touched(n, 0);
  const float k[2] = {static_cast<float>(front_scale / static_cast<double>(observed)),
                      static_cast<float>(behind_scale / static_cast<double>(observed))};
  for (const auto& partials : tile_partials)
    for (const Partial& part : partials) {
      for (int c = 0; c < 6; ++c) sums[part.id * 6 + c] += k[part.term] * part.d[c];
      touched[part.id] = 1;
    }
  const ViewTransform view(camera, pose);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    if (!touched[i]) return;
    ProjectionGrads pg;
    pg.mean2d = Eigen::Vector2f(sums[i * 6], sums[i * 6 + 1]);
    pg.conic = Eigen::Vector3f(sums[i * 6 + 2], sums[i * 6 + 3], sums[i * 6 + 4]);
    project_gaussian_backward(view, &model.means[i * 3], &model.log_scales[i * 3],
                              &model.quats[i * 4], pg, &grads->means[i * 3],
                              &grads->log_scales[i * 3], &grads->quats[i * 4]);
    const float o = 1.f / (1.f + std::exp(-model.opacity_logits[i]));
    grads->opacity_logits[i] += sums[i * 6 + 5] * o * (1 - o);
  });
  return loss;
}

}  // namespace gslift
