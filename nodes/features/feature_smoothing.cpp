#include "nodes/features/feature_smoothing.hpp"

#include <algorithm>

#include <open3d/geometry/KDTreeFlann.h>
#include <tbb/parallel_for.h>

namespace gslift {

FeatureSmoothing::FeatureSmoothing(const std::vector<float>& means, int k)
    : k_(std::max(1, std::min<int>(k, static_cast<int>(means.size() / 3)))), n_(means.size() / 3) {
  Eigen::MatrixXd pts(3, n_);
  for (size_t g = 0; g < n_; ++g)
    for (int a = 0; a < 3; ++a) pts(a, g) = means[3 * g + a];
  const open3d::geometry::KDTreeFlann tree(pts);
  neighbours_.resize(n_ * k_);
  tbb::parallel_for(size_t(0), n_, [&](size_t g) {
    std::vector<int> ids;
    std::vector<double> dist2;
    tree.SearchKNN(Eigen::Vector3d(pts.col(g)), k_, ids, dist2);
    // Coincident centres may list another Gaussian first: the Gaussian itself goes to slot 0.
    auto self = std::find(ids.begin(), ids.end(), static_cast<int>(g));
    if (self != ids.end())
      std::rotate(ids.begin(), self, self + 1);
    else
      ids.insert(ids.begin(), static_cast<int>(g)), ids.resize(k_);
    for (int s = 0; s < k_; ++s) neighbours_[g * k_ + s] = static_cast<uint32_t>(ids[s]);
  });
  reverse_offsets_.assign(n_ + 1, 0);
  for (uint32_t m : neighbours_) ++reverse_offsets_[m + 1];
  for (size_t m = 0; m < n_; ++m) reverse_offsets_[m + 1] += reverse_offsets_[m];
  reverse_.resize(neighbours_.size());
  std::vector<uint32_t> cursor(reverse_offsets_.begin(), reverse_offsets_.end() - 1);
  for (size_t e = 0; e < neighbours_.size(); ++e)
    reverse_[cursor[neighbours_[e]]++] = static_cast<uint32_t>(e);
}

void FeatureSmoothing::smooth(const float* unit, int dim, const std::vector<int>& slots,
                              float* out) const {
  const float inv = 1.f / static_cast<float>(slots.size());
  tbb::parallel_for(size_t(0), n_, [&](size_t g) {
    float* o = out + g * dim;
    std::fill(o, o + dim, 0.f);
    for (int s : slots) {
      const float* u = unit + size_t(neighbours_[g * k_ + s]) * dim;
      for (int c = 0; c < dim; ++c) o[c] += u[c];
    }
    for (int c = 0; c < dim; ++c) o[c] *= inv;
  });
}

void FeatureSmoothing::backward(const float* grad_out, int dim, const std::vector<int>& slots,
                                float* grad_unit) const {
  std::vector<uint8_t> used(k_, 0);
  for (int s : slots) used[s] = 1;
  const float inv = 1.f / static_cast<float>(slots.size());
  tbb::parallel_for(size_t(0), n_, [&](size_t m) {
    float* o = grad_unit + m * dim;
    for (uint32_t r = reverse_offsets_[m]; r < reverse_offsets_[m + 1]; ++r) {
      const uint32_t e = reverse_[r];
      if (!used[e % k_]) continue;
      const float* gr = grad_out + size_t(e / k_) * dim;
      for (int c = 0; c < dim; ++c) o[c] += inv * gr[c];
    }
  });
}

}  // namespace gslift
