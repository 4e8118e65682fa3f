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
  float d[6];
};

}  // namespace

double line_of_sight_loss(const GaussianModel& model, const Camera& camera, const Pose& pose,
                          const cv::Mat1f& prior_depth, const RenderOutput& forward,
                          double tolerance, double scale, ModelGrads* grads) {
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
  if (observed == 0) return 0.0;

  const int tiles = s.tile_count();
  std::vector<double> tile_loss(tiles, 0.0);
  std::vector<std::vector<Partial>> tile_partials(tiles);
  tbb::parallel_for(0, tiles, [&](int t) {
    struct Front {
      uint32_t id;
      float a, G, dx, dy;
      const TileGaussian* g;
    };
    std::vector<Front> front;
    const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
    const uint32_t count = s.tile_offsets[t + 1] - s.tile_offsets[t];
    const int tx = t % s.tiles_x, ty = t / s.tiles_x;
    for (int y = ty * kTileSize; y < std::min(s.height, (ty + 1) * kTileSize); ++y)
      for (int x = tx * kTileSize; x < std::min(s.width, (tx + 1) * kTileSize); ++x) {
        const float D = prior_depth(y, x);
        if (!(D > 0) || !std::isfinite(D)) continue;
        const float cut = static_cast<float>((1 - tolerance) * D);
        // The list is in blending order, front to back: the Gaussians in front are a prefix.
        // Alphas exactly as the forward pass blends them (raster_state.hpp blend_row).
        front.clear();
        double T = 1;
        for (uint32_t j = 0; j < count; ++j) {
          const TileGaussian& g = list[j];
          if (!(s.projections[g.id].depth < cut)) break;
          if (x < g.x0 || x >= g.x1 || y < g.y0 || y >= g.y1) continue;
          const float dx = g.mx - (float(x) + 0.5f), dy = g.my - (float(y) + 0.5f);
          const float power = (-0.5f * g.C * dy * dy - 0.5f * g.A * dx * dx) - g.B * dy * dx;
          if (power > 0.f || power < g.power_min) continue;
          const float G = blend_exp(power);
          const float a = std::min(kMaxAlpha, g.opacity * G);
          if (a < s.min_alpha) continue;
          if (T * (1.0 - a) < kMinTransmittance) break;  // where the forward pass stops
          front.push_back({g.id, a, G, dx, dy, &g});
          T *= 1.0 - a;
        }
        tile_loss[t] += 1.0 - T;
        if (!grads) continue;
        // F = 1 - prod (1 - a_k): dF/da_k = T / (1 - a_k); a = o G, G = exp(power).
        for (const Front& f : front) {
          if (f.a >= kMaxAlpha) continue;  // clamped: constant
          const float dF_da = static_cast<float>(T / (1.0 - f.a));
          const TileGaussian& g = *f.g;
          const float d_power = dF_da * f.a;
          tile_partials[t].push_back(
              {f.id,
               {-d_power * (g.A * f.dx + g.B * f.dy), -d_power * (g.C * f.dy + g.B * f.dx),
                -0.5f * d_power * f.dx * f.dx, -d_power * f.dx * f.dy,
                -0.5f * d_power * f.dy * f.dy, dF_da * f.G}});
        }
      }
  });
  double loss = 0;
  for (double l : tile_loss) loss += l;
  loss /= static_cast<double>(observed);
  if (!grads) return loss;

  // Per Gaussian, the screen-space partials summed in tile order, then through the projection.
  const size_t n = model.size();
  std::vector<float> sums(n * 6, 0.f);
  std::vector<char> touched(n, 0);
  const float k = static_cast<float>(scale / static_cast<double>(observed));
  for (const auto& partials : tile_partials)
    for (const Partial& part : partials) {
      for (int c = 0; c < 6; ++c) sums[part.id * 6 + c] += k * part.d[c];
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
