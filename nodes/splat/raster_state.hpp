// What the rasterizer's forward pass keeps for the backward pass and the render cache: the tile
// lists of projected Gaussians and the per-pixel blending state. Internal to nodes/splat.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "nodes/splat/projection.hpp"

namespace gslift {

constexpr int kTileSize = 16;
constexpr float kMaxAlpha = 0.99f;          // alpha clamp (3DGS)
constexpr float kMinTransmittance = 1e-4f;  // stop blending below this

// One Gaussian in one tile's depth-sorted list, with what blending needs packed together.
struct TileGaussian {
  float mx, my;   // 2D mean
  float A, B, C;  // conic
  float opacity;
  float power_min;  // log(min_alpha / opacity): below it alpha < min_alpha, no exp needed
  uint32_t id;      // Gaussian index
  uint32_t slot;    // index of this (Gaussian, tile) pair in Gaussian-major order
};

struct RasterState {
  int width = 0, height = 0, tiles_x = 0, tiles_y = 0;
  // Per-Gaussian blended values, N x channels: [rgb 3][depth 1][normal 3][features D][alpha 1],
  // each block present only when rendered (offset -1 otherwise).
  int channels = 0;
  int rgb_offset = -1, depth_offset = -1, normal_offset = -1, feature_offset = -1,
      alpha_offset = -1;
  int sh_degree = 0;    // degree evaluated
  float min_alpha = 0;  // RenderSettings::min_alpha
  std::vector<float> values;
  std::vector<float> background;               // per channel: the RGB background, 0 elsewhere
  std::vector<ProjectedGaussian> projections;  // N; radius 0 = not in any tile
  std::vector<uint32_t> slot_offsets;          // N + 1: Gaussian g owns slots [g], [g+1])
  std::vector<uint32_t> tile_offsets;          // tiles + 1
  std::vector<TileGaussian> tile_gaussians;    // all tiles' lists, front to back
  std::vector<float> final_transmittance;      // H x W
  std::vector<uint32_t> contributors;          // H x W: last contributing list index + 1
  std::vector<float> alpha_sum;  // H x W accumulated alpha, kept when the alpha block is rendered

  int tile_count() const { return tiles_x * tiles_y; }
};

// Blending weight test shared by every pass so that they agree bit for bit. Returns false when the
// Gaussian is skipped at pixel centre (px, py); otherwise gaussian = exp(power) and
// alpha = min(0.99, opacity * gaussian).
inline bool blend_alpha(const TileGaussian& g, float px, float py, float min_alpha, float& gaussian,
                        float& alpha) {
  const float dx = g.mx - px, dy = g.my - py;
  const float power = -0.5f * (g.A * dx * dx + g.C * dy * dy) - g.B * dx * dy;
  if (power > 0.f || power < g.power_min) return false;
  gaussian = std::exp(power);
  alpha = std::min(kMaxAlpha, g.opacity * gaussian);
  return alpha >= min_alpha;
}

// Front-to-back blending of one pixel over a tile list (3DGS): calls on(j, w_j = alpha_j T_j) for
// every contributing entry j, stops before the entry that would bring T below 1e-4. Returns the
// last contributing index + 1; transmittance receives the final T.
template <class OnContribution>
inline uint32_t blend_pixel(const TileGaussian* list, uint32_t count, float px, float py,
                            float min_alpha, float& transmittance, OnContribution&& on) {
  float T = 1.f;
  uint32_t last = 0;
  for (uint32_t j = 0; j < count; ++j) {
    float gaussian, alpha;
    if (!blend_alpha(list[j], px, py, min_alpha, gaussian, alpha)) continue;
    const float next_T = T * (1.f - alpha);
    if (next_T < kMinTransmittance) break;
    on(j, alpha * T);
    T = next_T;
    last = j + 1;
  }
  transmittance = T;
  return last;
}

}  // namespace gslift
