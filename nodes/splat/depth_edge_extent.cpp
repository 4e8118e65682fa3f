#include "nodes/splat/depth_edge_extent.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "nodes/splat/view_geometry.hpp"

namespace gslift {

DepthEdgeView::DepthEdgeView(const cv::Mat1f& nearest)
    : cols_(nearest.cols), bits_((nearest.total() + 63) / 64, 0), before_(bits_.size(), 0) {
  for (int y = 0; y < nearest.rows; ++y)
    for (int x = 0; x < nearest.cols; ++x) {
      if (!(nearest(y, x) > 0)) continue;
      const size_t i = size_t(y) * size_t(cols_) + size_t(x);
      bits_[i >> 6] |= uint64_t{1} << (i & 63);
      depths_.push_back(nearest(y, x));
    }
  for (size_t w = 1; w < bits_.size(); ++w)
    before_[w] = before_[w - 1] + uint32_t(__builtin_popcountll(bits_[w - 1]));
}

std::vector<DepthEdgeView> depth_edges(const std::vector<DepthObservation>& views, double jump,
                                       int radius) {
  std::vector<DepthEdgeView> edges;
  for (const DepthObservation& v : views) {
    const cv::Mat1b mask = depth_discontinuities(v.depth, jump, radius);
    cv::Mat1f nearest = cv::Mat1f::zeros(v.depth.size());
    for (int iw = 0; iw < v.depth.rows; ++iw)
      for (int iu = 0; iu < v.depth.cols; ++iu) {
        if (!mask(iw, iu)) continue;
        float& least = nearest(iw, iu);
        for (int y = std::max(0, iw - 1); y <= std::min(v.depth.rows - 1, iw + 1); ++y)
          for (int x = std::max(0, iu - 1); x <= std::min(v.depth.cols - 1, iu + 1); ++x) {
            const float d = v.depth(y, x);
            if (d > 0 && std::isfinite(d) && (least == 0 || d < least)) least = d;
          }
      }
    edges.emplace_back(nearest);
  }
  return edges;
}

double depth_edge_extent_loss(const GaussianModel& model,
                              const std::vector<DepthObservation>& views,
                              const std::vector<DepthEdgeView>& edges, double tolerance,
                              std::vector<float>* grad) {
  if (edges.size() != views.size())
    throw std::invalid_argument("depth_edge_extent_loss: the edges are not the views'");
  const size_t n = model.size();
  if (grad) grad->assign(n * 3, 0.f);
  if (n == 0) return 0;
  std::vector<double> per(n, 0.0);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const Eigen::Vector3d mean(model.means[i * 3], model.means[i * 3 + 1], model.means[i * 3 + 2]);
    // The rotation only where a view's edge test passes: most Gaussians lie on no edge.
    Eigen::Matrix3d R;
    bool rotated = false;
    const float* s = &model.log_scales[i * 3];
    for (size_t k = 0; k < views.size(); ++k) {
      const DepthObservation& v = views[k];
      const Eigen::Vector3d p = v.pose->to_camera(mean);
      if (!(p.z() > 0)) continue;
      const Camera& c = *v.camera;
      const double u = c.fx * p.x() / p.z() + c.cx, w = c.fy * p.y() / p.z() + c.cy;
      if (!(u >= 0 && w >= 0 && u < v.depth.cols && w < v.depth.rows)) continue;
      const int iu = static_cast<int>(u), iw = static_cast<int>(w);
      const float nearest = edges[k].nearest(iu, iw);
      if (!(nearest > 0)) continue;
      if (std::abs(p.z() - nearest) > tolerance * nearest) continue;
      if (!rotated) {
        R = model.rotation(i);
        rotated = true;
      }
      const Eigen::Vector3d ray = (mean - v.pose->centre()).normalized();
      double part[3], var = 0;
      for (int a = 0; a < 3; ++a) {
        const double cosine = R.col(a).dot(ray);
        part[a] = std::exp(2.0 * s[a]) * cosine * cosine;
        var += part[a];
      }
      if (!(var > 0)) continue;
      const double sigma = std::sqrt(var);
      per[i] += sigma;
      // d sigma / d s_a = exp(2 s_a) (a_a . d)^2 / sigma.
      if (grad)
        for (int a = 0; a < 3; ++a)
          (*grad)[i * 3 + a] += static_cast<float>(part[a] / (sigma * static_cast<double>(n)));
    }
  });
  double sum = 0;
  for (const double x : per) sum += x;  // in Gaussian order: the same at any thread count
  return sum / static_cast<double>(n);
}

}  // namespace gslift
