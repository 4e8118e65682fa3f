#include "nodes/splat/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

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

}  // namespace gslift
