#include "nodes/features/contrastive_loss.hpp"

#include <cmath>
#include <utility>
#include <vector>

namespace gslift {
namespace {

double smoothed_norm(const float* b, int dim) {
  double s = kCosineEps * kCosineEps;
  for (int c = 0; c < dim; ++c) s += double(b[c]) * b[c];
  return std::sqrt(s);
}

// The centroid a (with its smoothed norm) against the sampled features b: accumulates, for each
// pixel, g_p * dcos(a, b_p)/da into grad_a and writes g_p * dcos(a, b_p)/db_p into grad_b, with
//   dcos/da = b / (|a| |b|) - cos a / |a|^2,   dcos/db = a / (|a| |b|) - cos b / |b|^2.
// `hinge(cos)` gives (loss term, dterm/dcos) of one pixel. Returns the summed loss terms.
template <class Hinge>
double cosine_terms(const std::vector<double>& a, double a_norm, const float* b, int n, int dim,
                    Hinge hinge, std::vector<double>& grad_a, float* grad_b) {
  double loss = 0;
  for (int p = 0; p < n; ++p) {
    const float* bp = b + size_t(p) * dim;
    float* gp = grad_b + size_t(p) * dim;
    const double b_norm = smoothed_norm(bp, dim);
    double ab = 0;
    for (int c = 0; c < dim; ++c) ab += a[c] * bp[c];
    const double inv = 1.0 / (a_norm * b_norm);
    const double cos = ab * inv;
    const auto [term, g] = hinge(cos);
    loss += term;
    if (g == 0) {
      for (int c = 0; c < dim; ++c) gp[c] = 0.f;
      continue;
    }
    const double ca = cos / (a_norm * a_norm), cb = cos / (b_norm * b_norm);
    for (int c = 0; c < dim; ++c) {
      grad_a[c] += g * (bp[c] * inv - ca * a[c]);
      gp[c] = static_cast<float>(g * (a[c] * inv - cb * bp[c]));
    }
  }
  return loss;
}

}  // namespace

double mask_contrastive_loss(const float* inside, int n_in, const float* outside, int n_out,
                             int dim, double lambda, float* grad_inside, float* grad_outside) {
  std::vector<double> centroid(dim, 0.0);
  for (int p = 0; p < n_in; ++p)
    for (int c = 0; c < dim; ++c) centroid[c] += inside[size_t(p) * dim + c];
  double norm2 = kCosineEps * kCosineEps;
  for (int c = 0; c < dim; ++c) {
    centroid[c] /= n_in;
    norm2 += centroid[c] * centroid[c];
  }
  const double centroid_norm = std::sqrt(norm2);

  std::vector<double> grad_centroid(dim, 0.0);
  const double w_in = 1.0 / n_in;
  double loss = cosine_terms(
      centroid, centroid_norm, inside, n_in, dim,
      [&](double cos) {
        return std::pair<double, double>{w_in * (1 - cos), -w_in};
      },
      grad_centroid, grad_inside);
  if (n_out > 0) {
    const double w_out = lambda / n_out;
    loss += cosine_terms(
        centroid, centroid_norm, outside, n_out, dim,
        [&](double cos) {
          return cos > 0 ? std::pair<double, double>{w_out * cos, w_out}
                         : std::pair<double, double>{0.0, 0.0};
        },
        grad_centroid, grad_outside);
  }
  // f_m = mean of the inside features: each receives 1/n_in of the centroid's gradient.
  for (int p = 0; p < n_in; ++p)
    for (int c = 0; c < dim; ++c)
      grad_inside[size_t(p) * dim + c] += static_cast<float>(grad_centroid[c] * w_in);
  return loss;
}

}  // namespace gslift
