#include "nodes/splat/free_space_extent.hpp"

#include <cmath>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace gslift {

bool in_observed_free_space(const Eigen::Vector3d& x, const std::vector<DepthObservation>& views,
                            double tolerance) {
  for (const DepthObservation& v : views) {
    const Eigen::Vector3d p = v.pose->to_camera(x);
    if (!(p.z() > 0)) continue;
    const Camera& c = *v.camera;
    const double u = c.fx * p.x() / p.z() + c.cx, w = c.fy * p.y() / p.z() + c.cy;
    if (!(u >= 0 && w >= 0 && u < v.depth.cols && w < v.depth.rows)) continue;
    const float d = v.depth(static_cast<int>(w), static_cast<int>(u));
    if (d > 0 && std::isfinite(d) && p.z() < (1 - tolerance) * d) return true;
  }
  return false;
}

size_t clamp_extent_to_free_space(GaussianModel& model, const std::vector<DepthObservation>& views,
                                  const ExtentClampOptions& options) {
  if (!options.active() || views.empty()) return 0;
  const double log_half = std::log(0.5);
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, model.size()), size_t{0},
      [&](const tbb::blocked_range<size_t>& range, size_t shrunk) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          const Eigen::Vector3d mean(model.means[i * 3], model.means[i * 3 + 1],
                                     model.means[i * 3 + 2]);
          if (in_observed_free_space(mean, views, options.tolerance)) continue;
          const Eigen::Matrix3d R = model.rotation(i);
          for (int a = 0; a < 3; ++a) {
            float& log_scale = model.log_scales[i * 3 + a];
            const auto overhangs = [&] {
              const Eigen::Vector3d reach = options.sigmas * std::exp(log_scale) * R.col(a);
              return in_observed_free_space(mean + reach, views, options.tolerance) ||
                     in_observed_free_space(mean - reach, views, options.tolerance);
            };
            if (!overhangs()) continue;
            ++shrunk;
            for (int h = 0; h < options.max_halvings; ++h) {
              log_scale += static_cast<float>(log_half);
              if (!overhangs()) break;
            }
          }
        }
        return shrunk;
      },
      std::plus<size_t>());
}

}  // namespace gslift
