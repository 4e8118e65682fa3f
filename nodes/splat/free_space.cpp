#include "nodes/splat/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"

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
  std::vector<float> z(n);
  for (const DepthObservation& v : views) {
    const RenderOutput forward = render(model, *v.camera, *v.pose, weights_only);
    if (forward.width != v.depth.cols || forward.height != v.depth.rows)
      throw std::invalid_argument("line_of_sight_weights: a depth prior is not the view's size");
    const RenderCache cache(forward);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      z[i] = static_cast<float>(
          v.pose
              ->to_camera(Eigen::Vector3d(model.means[i * 3], model.means[i * 3 + 1],
                                          model.means[i * 3 + 2]))
              .z());
    });
    const auto& offsets = cache.pixel_offsets();
    const auto& ids = cache.ids();
    const auto& weights = cache.weights();
    // Fixed bands of rows, each summed into its own pair of vectors and then added in band order:
    // the same sums at any thread count.
    const int rows = v.depth.rows, cols = v.depth.cols, band = 32;
    const int bands = (rows + band - 1) / band;
    std::vector<LineOfSightWeights> partial(bands);
    tbb::parallel_for(0, bands, [&](int b) {
      LineOfSightWeights& part = partial[b];
      part.free_space.assign(n, 0.0);
      part.on_surface.assign(n, 0.0);
      part.unobserved.assign(n, 0.0);
      part.behind.assign(n, 0.0);
      for (int y = b * band; y < std::min(rows, (b + 1) * band); ++y)
        for (int x = 0; x < cols; ++x) {
          const float d = v.depth(y, x);
          const size_t p = static_cast<size_t>(y) * cols + x;
          if (!(d > 0) || !std::isfinite(d)) {
            for (uint32_t k = offsets[p]; k < offsets[p + 1]; ++k)
              part.unobserved[ids[k]] += weights[k];
            continue;
          }
          for (uint32_t k = offsets[p]; k < offsets[p + 1]; ++k) {
            const uint32_t i = ids[k];
            if (z[i] < (1 - tolerance) * d) {
              part.free_space[i] += weights[k];
              continue;
            }
            part.on_surface[i] += weights[k];
            if (z[i] > (1 + tolerance) * d) part.behind[i] += weights[k];
          }
        }
    });
    for (const LineOfSightWeights& part : partial)
      for (size_t i = 0; i < n; ++i) {
        out.free_space[i] += part.free_space[i];
        out.on_surface[i] += part.on_surface[i];
        out.unobserved[i] += part.unobserved[i];
        out.behind[i] += part.behind[i];
      }
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
