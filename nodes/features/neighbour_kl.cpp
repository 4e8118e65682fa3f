#include "nodes/features/neighbour_kl.hpp"

#include <algorithm>
#include <cmath>

#include <open3d/geometry/KDTreeFlann.h>
#include <tbb/parallel_for.h>
#include <Eigen/Core>

namespace gslift {
namespace {

constexpr double kLogEps = 1e-10;  // Gaga / Gaussian Grouping: log(p + 1e-10)

// softmax(W f + b) of one Gaussian.
void class_probabilities(const float* f, int dim, const float* weights, const float* bias,
                         int classes, std::vector<double>& p) {
  p.resize(classes);
  double top = -1e300;
  for (int c = 0; c < classes; ++c) {
    double s = bias[c];
    for (int d = 0; d < dim; ++d) s += double(weights[size_t(c) * dim + d]) * f[d];
    p[c] = s;
    top = std::max(top, s);
  }
  double sum = 0;
  for (double& v : p) sum += (v = std::exp(v - top));
  for (double& v : p) v /= sum;
}

}  // namespace

struct GaussianNeighbours::Tree {
  Eigen::MatrixXd points;
  open3d::geometry::KDTreeFlann flann;
};

GaussianNeighbours::GaussianNeighbours(const std::vector<float>& means)
    : tree_(std::make_unique<Tree>()), n_(means.size() / 3) {
  tree_->points.resize(3, static_cast<Eigen::Index>(n_));
  for (size_t i = 0; i < n_; ++i)
    for (int c = 0; c < 3; ++c) tree_->points(c, static_cast<Eigen::Index>(i)) = means[3 * i + c];
  tree_->flann.SetMatrixData(tree_->points);
}

GaussianNeighbours::~GaussianNeighbours() = default;

std::vector<int> GaussianNeighbours::nearest(const std::vector<int>& queries, int k) const {
  std::vector<int> out(queries.size() * size_t(k));
  tbb::parallel_for(size_t(0), queries.size(), [&](size_t s) {
    std::vector<int> idx;
    std::vector<double> d2;
    tree_->flann.SearchKNN(Eigen::Vector3d(tree_->points.col(queries[s])), k, idx, d2);
    // Equal distances (the sample and a copy of it) come back in the tree's order; the sample
    // itself first keeps the result independent of that order.
    auto self = std::find(idx.begin(), idx.end(), queries[s]);
    if (self != idx.end()) std::rotate(idx.begin(), self, self + 1);
    for (int j = 0; j < k; ++j)
      out[s * k + j] = idx.empty() ? queries[s] : idx[std::min<size_t>(j, idx.size() - 1)];
  });
  return out;
}

double neighbour_kl_loss(const float* features, int dim, const float* weights, const float* bias,
                         int classes, const std::vector<int>& samples,
                         const std::vector<int>& neighbours, int k, double lambda,
                         float* grad_features, float* grad_weights, float* grad_bias) {
  if (samples.empty() || k <= 0) return 0;
  const double scale = lambda / (double(classes) * samples.size() * k);
  std::vector<double> p, q, gp(classes), gq(classes);
  // dL/dz for z = W f + b of a Gaussian whose probabilities are r and dL/dr = g:
  // dz_c = r_c (g_c - sum_d r_d g_d); then df = W^T dz, dW += dz f^T, db += dz.
  auto backward = [&](int gaussian, const std::vector<double>& r, const std::vector<double>& g) {
    double dot = 0;
    for (int c = 0; c < classes; ++c) dot += r[c] * g[c];
    const float* f = features + size_t(gaussian) * dim;
    float* gf = grad_features + size_t(gaussian) * dim;
    for (int c = 0; c < classes; ++c) {
      const double dz = r[c] * (g[c] - dot);
      if (dz == 0) continue;
      grad_bias[c] += static_cast<float>(dz);
      for (int d = 0; d < dim; ++d) {
        gf[d] += static_cast<float>(dz * weights[size_t(c) * dim + d]);
        grad_weights[size_t(c) * dim + d] += static_cast<float>(dz * f[d]);
      }
    }
  };
  double loss = 0;
  for (size_t s = 0; s < samples.size(); ++s) {
    class_probabilities(features + size_t(samples[s]) * dim, dim, weights, bias, classes, p);
    std::fill(gp.begin(), gp.end(), 0.0);
    for (int j = 0; j < k; ++j) {
      const int n = neighbours[s * k + j];
      class_probabilities(features + size_t(n) * dim, dim, weights, bias, classes, q);
      for (int c = 0; c < classes; ++c) {
        const double lp = std::log(p[c] + kLogEps), lq = std::log(q[c] + kLogEps);
        loss += scale * p[c] * (lp - lq);
        gp[c] += scale * (lp - lq + p[c] / (p[c] + kLogEps));
        gq[c] = -scale * p[c] / (q[c] + kLogEps);
      }
      backward(n, q, gq);
    }
    backward(samples[s], p, gp);
  }
  return loss;
}

}  // namespace gslift
