// Vector width of the blending loops it shares with the rasterizer: see rasterizer_forward.cpp.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

FreeSpaceCounts free_space_counts(const GaussianModel& model,
                                  const std::vector<DepthObservation>& views, double tolerance) {
  const size_t n = model.size();
  FreeSpaceCounts counts;
  counts.in_free_space.assign(n, 0);
  counts.seen.assign(n, 0);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const Eigen::Vector3d x(model.means[i * 3], model.means[i * 3 + 1], model.means[i * 3 + 2]);
    int free = 0, seen = 0;
    for (const DepthObservation& v : views) {
      const Eigen::Vector3d p = v.pose->to_camera(x);
      if (!(p.z() > 0)) continue;
      const Camera& c = *v.camera;
      const double u = c.fx * p.x() / p.z() + c.cx, w = c.fy * p.y() / p.z() + c.cy;
      if (!(u >= 0 && w >= 0 && u < c.width && w < c.height)) continue;
      const int iu = static_cast<int>(u), iv = static_cast<int>(w);
      float lo = std::numeric_limits<float>::infinity(), hi = 0;
      for (int y = std::max(iv - 1, 0); y <= std::min(iv + 1, v.depth.rows - 1); ++y)
        for (int x2 = std::max(iu - 1, 0); x2 <= std::min(iu + 1, v.depth.cols - 1); ++x2) {
          const float d = v.depth(y, x2);
          if (!(d > 0) || !std::isfinite(d)) continue;
          lo = std::min(lo, d);
          hi = std::max(hi, d);
        }
      if (!(hi > 0)) continue;
      if (p.z() < (1 - tolerance) * lo) ++free;
      if (p.z() <= (1 + tolerance) * hi) ++seen;
    }
    counts.in_free_space[i] = static_cast<uint8_t>(std::min(free, 255));
    counts.seen[i] = static_cast<uint8_t>(std::min(seen, 255));
  });
  return counts;
}

std::vector<char> free_space_prune_mask(const FreeSpaceCounts& counts,
                                        const FreeSpacePruneOptions& o) {
  std::vector<char> prune(counts.seen.size(), 0);
  for (size_t i = 0; i < prune.size(); ++i)
    prune[i] = (o.free_space_views > 0 && counts.in_free_space[i] >= o.free_space_views) ||
               (o.min_seen_views > 0 && counts.seen[i] < o.min_seen_views);
  return prune;
}

LineOfSightWeights line_of_sight_weights(const GaussianModel& model,
                                         const std::vector<DepthObservation>& views,
                                         double tolerance) {
  const size_t n = model.size();
  LineOfSightWeights out;
  out.free_space.assign(n, 0.0);
  out.on_surface.assign(n, 0.0);
  out.unobserved.assign(n, 0.0);
  out.behind.assign(n, 0.0);
  RenderSettings weights_only;
  weights_only.rgb = false;
  // Per slot (one Gaussian's entry in one tile's list), its weight over the tile's pixels in four
  // parts: in free space, on the surface (behind it included), unobserved, behind. Summed while the
  // forward pass's blending runs again (blend_tile), with no per-pixel lists: a pruning round costs
  // two blending passes per view, not a render cache's three and its pairs.
  enum Part { kFree, kOnSurface, kUnobserved, kBehind, kParts };
  const float below = static_cast<float>(1 - tolerance), above = static_cast<float>(1 + tolerance);
  for (const DepthObservation& v : views) {
    const RenderOutput forward = render(model, *v.camera, *v.pose, weights_only);
    if (forward.width != v.depth.cols || forward.height != v.depth.rows)
      throw std::invalid_argument("line_of_sight_weights: a depth prior is not the view's size");
    const RasterState& s = *forward.state;
    UninitVector<float> slots(s.tile_gaussians.size() * kParts);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, s.tile_count()), [&](const tbb::blocked_range<int>& r) {
          TileBlend blend;
          // Per tile pixel, the depths that bound the observed surface (a pixel without a prior is
          // unobserved: every test below fails there but `unobserved`).
          alignas(64) float lower[kTilePixels], upper[kTilePixels], observed[kTilePixels];
          for (int t = r.begin(); t != r.end(); ++t) {
            const PixelRect tile = tile_pixels(s, t);
            for (int p = 0; p < kTilePixels; ++p) {
              const int x = tile.x0 + p % kTileSize, y = tile.y0 + p / kTileSize;
              const float d = x < tile.x1 && y < tile.y1 ? v.depth(y, x) : 0.f;
              const bool has = d > 0 && std::isfinite(d);
              observed[p] = has ? 1.f : 0.f;
              lower[p] = has ? below * d : 0.f;
              upper[p] = has ? above * d : std::numeric_limits<float>::infinity();
            }
            const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
            for (uint32_t j = 0; j < s.tile_offsets[t + 1] - s.tile_offsets[t]; ++j)
              std::fill_n(&slots[size_t(list[j].slot) * kParts], kParts, 0.f);
            blend_tile(s, t, blend, [&](uint32_t j, int at, const float* w) {
              const float z = s.projections[list[j].id].depth;
              float part[kParts] = {};
              for (int x = 0; x < kLanes; ++x) {
                const bool has = observed[at + x] != 0.f, free = z < lower[at + x];
                part[kFree] += has && free ? w[x] : 0.f;
                part[kOnSurface] += has && !free ? w[x] : 0.f;
                part[kUnobserved] += has ? 0.f : w[x];
                part[kBehind] += z > upper[at + x] ? w[x] : 0.f;
              }
              float* slot = &slots[size_t(list[j].slot) * kParts];
              for (int k = 0; k < kParts; ++k) slot[k] += part[k];
            });
          }
        });
    // Each Gaussian's slots in slot order: the same sums at any thread count.
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      for (uint32_t k = s.slot_offsets[i]; k < s.slot_offsets[i + 1]; ++k) {
        const float* slot = &slots[size_t(k) * kParts];
        out.free_space[i] += slot[kFree];
        out.on_surface[i] += slot[kOnSurface];
        out.unobserved[i] += slot[kUnobserved];
        out.behind[i] += slot[kBehind];
      }
    });
  }
  return out;
}

std::vector<char> line_of_sight_prune_mask(const LineOfSightWeights& w, double fraction,
                                           double behind) {
  std::vector<char> prune(w.free_space.size(), 0);
  for (size_t i = 0; i < prune.size(); ++i) {
    const double observed = w.free_space[i] + w.on_surface[i];
    prune[i] = (fraction > 0 && w.free_space[i] > fraction * observed) ||
               (behind > 0 && w.behind[i] > behind * observed);
  }
  return prune;
}

std::vector<char> FreeSpacePruner::prune_mask(const GaussianModel& model,
                                              const std::vector<DepthObservation>& views) {
  const FreeSpacePruneOptions& o = options_;
  std::vector<char> prune(model.size(), 0);
  if (o.free_space_views > 0 || o.min_seen_views > 0)
    prune = free_space_prune_mask(free_space_counts(model, views, o.tolerance), o);
  if (o.line_of_sight > 0 || o.behind > 0) {
    const std::vector<char> los = line_of_sight_prune_mask(
        line_of_sight_weights(model, views, o.tolerance), o.line_of_sight, o.behind);
    streak_.resize(model.size(), 0);
    for (size_t i = 0; i < prune.size(); ++i) {
      streak_[i] = los[i] ? static_cast<uint8_t>(std::min(streak_[i] + 1, 255)) : 0;
      prune[i] = prune[i] || streak_[i] >= o.line_of_sight_rounds;
    }
  }
  return prune;
}

void FreeSpacePruner::remap(const std::vector<int>& source) {
  if (streak_.empty()) return;
  std::vector<uint8_t> next(source.size(), 0);
  for (size_t i = 0; i < source.size(); ++i)
    if (source[i] >= 0) next[i] = streak_[source[i]];
  streak_ = std::move(next);
}

}  // namespace gslift
