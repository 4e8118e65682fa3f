#include "nodes/features/classifier_loss.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "nodes/features/contrastive_loss.hpp"

namespace gslift {
namespace {

double smoothed_norm(const float* v, int dim) {
  double s = kCosineEps * kCosineEps;
  for (int c = 0; c < dim; ++c) s += double(v[c]) * v[c];
  return std::sqrt(s);
}

// softmax(logits) in place; returns -log p[label].
double softmax_ce(std::vector<double>& logits, int label) {
  const double top = *std::max_element(logits.begin(), logits.end());
  double sum = 0;
  for (double& l : logits) sum += (l = std::exp(l - top));
  for (double& l : logits) l /= sum;
  return -std::log(std::max(logits[label], 1e-300));
}

}  // namespace

double cosine_classifier_loss(const float* features, int n, int dim, const int* labels,
                              const float* weights, int classes, double tau, float* grad_features,
                              float* grad_weights) {
  std::vector<double> w_norm(classes);
  for (int c = 0; c < classes; ++c) w_norm[c] = smoothed_norm(weights + size_t(c) * dim, dim);
  std::vector<double> cos(classes), p(classes), gf(dim);
  double loss = 0;
  const double inv_n = 1.0 / n;
  for (int i = 0; i < n; ++i) {
    const float* f = features + size_t(i) * dim;
    const double f_norm = smoothed_norm(f, dim);
    for (int c = 0; c < classes; ++c) {
      const float* w = weights + size_t(c) * dim;
      double s = 0;
      for (int d = 0; d < dim; ++d) s += double(w[d]) * f[d];
      cos[c] = s / (w_norm[c] * f_norm);
      p[c] = tau * cos[c];
    }
    loss += softmax_ce(p, labels[i]) * inv_n;
    // dL/dlogit_c = (p_c - [c = y]) / n; dcos/dF = w/(|w||F|) - cos F/|F|^2, dcos/dw likewise.
    std::fill(gf.begin(), gf.end(), 0.0);
    for (int c = 0; c < classes; ++c) {
      const double g = tau * (p[c] - (c == labels[i] ? 1.0 : 0.0)) * inv_n;
      if (g == 0) continue;
      const float* w = weights + size_t(c) * dim;
      float* gw = grad_weights + size_t(c) * dim;
      const double inv = 1.0 / (w_norm[c] * f_norm);
      const double cf = cos[c] / (f_norm * f_norm), cw = cos[c] / (w_norm[c] * w_norm[c]);
      for (int d = 0; d < dim; ++d) {
        gf[d] += g * (w[d] * inv - cf * f[d]);
        gw[d] += static_cast<float>(g * (f[d] * inv - cw * w[d]));
      }
    }
    for (int d = 0; d < dim; ++d) grad_features[size_t(i) * dim + d] = static_cast<float>(gf[d]);
  }
  return loss;
}

double linear_classifier_loss(const float* features, int n, int dim, const int* labels,
                              const float* weights, const float* bias, int classes,
                              float* grad_features, float* grad_weights, float* grad_bias) {
  std::vector<double> p(classes), gf(dim);
  const double scale = 1.0 / (n * std::log(std::max(classes, 2)));
  double loss = 0;
  for (int i = 0; i < n; ++i) {
    const float* f = features + size_t(i) * dim;
    for (int c = 0; c < classes; ++c) {
      const float* w = weights + size_t(c) * dim;
      double s = bias[c];
      for (int d = 0; d < dim; ++d) s += double(w[d]) * f[d];
      p[c] = s;
    }
    loss += softmax_ce(p, labels[i]) * scale;
    std::fill(gf.begin(), gf.end(), 0.0);
    for (int c = 0; c < classes; ++c) {
      const double g = (p[c] - (c == labels[i] ? 1.0 : 0.0)) * scale;
      const float* w = weights + size_t(c) * dim;
      float* gw = grad_weights + size_t(c) * dim;
      grad_bias[c] += static_cast<float>(g);
      for (int d = 0; d < dim; ++d) {
        gf[d] += g * w[d];
        gw[d] += static_cast<float>(g * f[d]);
      }
    }
    for (int d = 0; d < dim; ++d) grad_features[size_t(i) * dim + d] = static_cast<float>(gf[d]);
  }
  return loss;
}

}  // namespace gslift
