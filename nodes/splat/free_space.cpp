// Vector width of the blending loops it shares with the rasterizer: see rasterizer_forward.cpp.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC target("prefer-vector-width=512")
#endif
#include "nodes/splat/free_space.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/ray_depth.hpp"

namespace gslift {

namespace {

// The depths that bound the observed surface at each pixel of a tile: lower = (1 - tolerance) D,
// upper = (1 + tolerance) D, observed = 1 where the pixel has a prior; a pixel without one (or
// outside the image) gets lower 0 and upper infinity, so every test but "unobserved" fails there.
struct TilePrior {
  alignas(64) float lower[kTilePixels], upper[kTilePixels], observed[kTilePixels];
  TilePrior(const cv::Mat1f& depth, const PixelRect& tile, float below, float above) {
    for (int p = 0; p < kTilePixels; ++p) {
      const int x = tile.x0 + p % kTileSize, y = tile.y0 + p / kTileSize;
      const float d = x < tile.x1 && y < tile.y1 ? depth(y, x) : 0.f;
      const bool has = d > 0 && std::isfinite(d);
      observed[p] = has ? 1.f : 0.f;
      lower[p] = has ? below * d : 0.f;
      upper[p] = has ? above * d : std::numeric_limits<float>::infinity();
    }
  }
};

// Adds one view's per-Gaussian sums to sums[part]: tile_pass(s, t, prior, slots) runs over the
// view's tiles in parallel and writes kParts numbers per entry of tile t's list into
// slots[entry.slot * kParts ...] (no per-pixel lists); each Gaussian's slots are then added in slot
// order, the same sums at any thread count.
template <int kParts, class EntryDepth, class TilePass>
void add_view_sums(const RasterState& s, const cv::Mat1f& depth, float below, float above,
                   const EntryDepth& entry_depth,
                   const std::array<std::vector<double>*, kParts>& sums, TilePass&& tile_pass) {
  UninitVector<float> slots(s.tile_gaussians.size() * kParts);
  tbb::parallel_for(tbb::blocked_range<int>(0, s.tile_count()),
                    [&](const tbb::blocked_range<int>& r) {
                      for (int t = r.begin(); t != r.end(); ++t)
                        tile_pass(s, t, TilePrior(depth, tile_pixels(s, t), below, above),
                                  entry_depth, slots.data());
                    });
  tbb::parallel_for(size_t(0), sums[0]->size(), [&](size_t i) {
    for (uint32_t k = s.slot_offsets[i]; k < s.slot_offsets[i + 1]; ++k)
      for (int part = 0; part < kParts; ++part)
        (*sums[part])[i] += slots[size_t(k) * kParts + part];
  });
}

// Per slot (one Gaussian's entry in one tile's list), its weight over the tile's pixels in four
// parts: in free space, on the surface (behind it included), unobserved, behind. Summed while the
// forward pass's blending runs again (blend_tile): a pruning round costs two blending passes per
// view, not a render cache's three and its pairs.
enum WeightPart { kFree, kOnSurface, kUnobserved, kBehind, kWeightParts };
template <class EntryDepth>
void line_of_sight_tile(const RasterState& s, int t, const TilePrior& prior,
                        const EntryDepth& entry_depth, float* slots) {
  const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
  for (uint32_t j = 0; j < s.tile_offsets[t + 1] - s.tile_offsets[t]; ++j)
    std::fill_n(&slots[size_t(list[j].slot) * kWeightParts], kWeightParts, 0.f);
  const PixelRect tile = tile_pixels(s, t);
  TileBlend blend;
  blend_tile(s, t, blend, [&](uint32_t j, int at, const float* w, const RowLanes&) {
    alignas(64) float z[kLanes];
    entry_depth.row(list[j].id, tile.y0 + at / kTileSize, tile.x0, z);
    // Per part, the row's lanes summed pairwise (lane_sums): a vector loop, where a running
    // scalar sum per part compiled to 16 scalar iterations with branches per entry row.
    alignas(64) float part[kWeightParts][kLanes];
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
    for (int x = 0; x < kLanes; ++x) {
      const bool has = prior.observed[at + x] != 0.f, free = z[x] < prior.lower[at + x];
      part[kFree][x] = has && free ? w[x] : 0.f;
      part[kOnSurface][x] = has && !free ? w[x] : 0.f;
      part[kUnobserved][x] = has ? 0.f : w[x];
      part[kBehind][x] = z[x] > prior.upper[at + x] ? w[x] : 0.f;
    }
    LaneVector parts[kWeightParts];
    for (int k = 0; k < kWeightParts; ++k) parts[k] = load_lanes(part[k]);
    float sums[kWeightParts];
    lane_sums(parts, kWeightParts, sums);
    float* slot = &slots[size_t(list[j].slot) * kWeightParts];
    for (int k = 0; k < kWeightParts; ++k) slot[k] += sums[k];
  });
}

// Per slot, the entry's own opacity over the tile's pixels with a prior, and the part of it behind
// the prior. Every entry of the list, past where blending would stop: the part of a footprint that
// the surfaces in front hide is what this pass is for.
enum FootprintPart { kObserved, kHidden, kFootprintParts };
template <class EntryDepth>
void footprint_tile(const RasterState& s, int t, const TilePrior& prior,
                    const EntryDepth& entry_depth, float* slots) {
  const PixelRect tile = tile_pixels(s, t);
  const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
  alignas(64) float gaussian[kLanes], alpha[kLanes], z[kLanes];
  for (uint32_t j = 0; j < s.tile_offsets[t + 1] - s.tile_offsets[t]; ++j) {
    const TileGaussian& e = list[j];
    const PixelRect rect = clip(e, tile);
    // Lane accumulators over the entry's rows, summed pairwise once per entry (lane_sums).
    alignas(64) float part[kFootprintParts][kLanes];
    for (auto& lanes : part) store_lanes(lanes, LaneVector{});
    for (int y = rect.y0; y < rect.y1; ++y) {
      blend_row(e, y, tile.x0, tile.x0 + kLanes, s.min_alpha, gaussian, alpha);
      entry_depth.row(e.id, y, tile.x0, z);
      const int at = (y - tile.y0) * kTileSize;
#pragma GCC unroll 1  // one vector loop, not kLanes scalar copies
      for (int x = 0; x < kLanes; ++x) {
        const int px = tile.x0 + x;
        const float a = ((px >= rect.x0) & (px < rect.x1) & (alpha[x] >= 0.f)) ? alpha[x] : 0.f;
        part[kObserved][x] += prior.observed[at + x] != 0.f ? a : 0.f;
        part[kHidden][x] += z[x] > prior.upper[at + x] ? a : 0.f;
      }
    }
    LaneVector parts[kFootprintParts];
    for (int k = 0; k < kFootprintParts; ++k) parts[k] = load_lanes(part[k]);
    lane_sums(parts, kFootprintParts, &slots[size_t(e.slot) * kFootprintParts]);
  }
}

// The line-of-sight weights and the footprints over the training views, from one render of each
// view (weights only); either output may be null.
void sum_over_views(const GaussianModel& model, const std::vector<DepthObservation>& views,
                    double tolerance, bool ray_depth, LineOfSightWeights* weights,
                    FootprintDepth* footprint) {
  const size_t n = model.size();
  if (weights)
    for (auto* sum :
         {&weights->free_space, &weights->on_surface, &weights->unobserved, &weights->behind})
      sum->assign(n, 0.0);
  if (footprint)
    for (auto* sum : {&footprint->observed, &footprint->behind}) sum->assign(n, 0.0);
  RenderSettings weights_only;
  weights_only.rgb = false;
  const float below = static_cast<float>(1 - tolerance), above = static_cast<float>(1 + tolerance);
  for (const DepthObservation& v : views) {
    const RenderOutput forward = render(model, *v.camera, *v.pose, weights_only);
    if (forward.width != v.depth.cols || forward.height != v.depth.rows)
      throw std::invalid_argument("line-of-sight tests: a depth prior is not the view's size");
    const RasterState& s = *forward.state;
    with_entry_depths(ray_depth, model, *v.camera, *v.pose, s, [&](const auto& entry_depth) {
      using EntryDepth = std::decay_t<decltype(entry_depth)>;
      if (weights)
        add_view_sums<kWeightParts>(
            s, v.depth, below, above, entry_depth,
            {&weights->free_space, &weights->on_surface, &weights->unobserved, &weights->behind},
            line_of_sight_tile<EntryDepth>);
      if (footprint)
        add_view_sums<kFootprintParts>(s, v.depth, below, above, entry_depth,
                                       {&footprint->observed, &footprint->behind},
                                       footprint_tile<EntryDepth>);
    });
  }
}

}  // namespace

LineOfSightWeights line_of_sight_weights(const GaussianModel& model,
                                         const std::vector<DepthObservation>& views,
                                         double tolerance, bool ray_depth) {
  LineOfSightWeights out;
  sum_over_views(model, views, tolerance, ray_depth, &out, nullptr);
  return out;
}

FootprintDepth footprint_behind(const GaussianModel& model,
                                const std::vector<DepthObservation>& views, double tolerance,
                                bool ray_depth) {
  FootprintDepth out;
  sum_over_views(model, views, tolerance, ray_depth, nullptr, &out);
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
  if (o.line_of_sight > 0 || o.behind > 0 || o.hidden > 0) {
    // One render per view serves both the weights and the footprints.
    const bool by_weight = o.line_of_sight > 0 || o.behind > 0;
    LineOfSightWeights weights;
    FootprintDepth footprint;
    sum_over_views(model, views, o.tolerance, o.ray_depth, by_weight ? &weights : nullptr,
                   o.hidden > 0 ? &footprint : nullptr);
    std::vector<char> violates(model.size(), 0);
    if (by_weight) violates = line_of_sight_prune_mask(weights, o.line_of_sight, o.behind);
    for (size_t i = 0; i < violates.size() && o.hidden > 0; ++i)
      violates[i] = violates[i] || footprint.behind[i] > o.hidden * footprint.observed[i];
    streak_.resize(model.size(), 0);
    for (size_t i = 0; i < prune.size(); ++i) {
      streak_[i] = violates[i] ? static_cast<uint8_t>(std::min(streak_[i] + 1, 255)) : 0;
      prune[i] = streak_[i] >= o.line_of_sight_rounds;
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
