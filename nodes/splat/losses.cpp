#include "nodes/splat/losses.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/splat/ssim.hpp"

namespace gslift {
namespace {

void require_same(const cv::Mat& a, const cv::Mat& b, int type, const char* what) {
  if (a.size() != b.size() || a.type() != type || b.type() != type)
    throw std::invalid_argument(std::string(what) + ": rendered and target differ in size or type");
}

bool valid_depth(float d) {
  return d > 0.f && std::isfinite(d);
}

// Sum over rows of fn(row): rows in parallel, the partial sums added in row order, so the result is
// the same at any thread count.
template <class RowFn>
double sum_over_rows(int rows, const RowFn& fn) {
  std::vector<double> partial(rows, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 8), [&](const tbb::blocked_range<int>& range) {
    for (int r = range.begin(); r < range.end(); ++r) partial[r] = fn(r);
  });
  double sum = 0;
  for (double p : partial) sum += p;
  return sum;
}

}  // namespace

PhotometricLoss photometric_loss(const cv::Mat& rendered, const SsimTarget& target,
                                 double ssim_lambda, cv::Mat* grad) {
  require_same(rendered, target.image, CV_32FC3, "photometric_loss");
  PhotometricLoss loss;
  cv::Mat ssim_grad;
  loss.ssim = ssim(rendered, target, grad && ssim_lambda != 0 ? &ssim_grad : nullptr);
  const double count = static_cast<double>(rendered.total() * 3);
  const int width = rendered.cols * 3;
  // d|x|/dx = sign(x) (sign(0) = 0 like torch), scaled by the L1 weight over the mean's count.
  const float l1_step = static_cast<float>((1 - ssim_lambda) / count);
  const float ssim_scale = static_cast<float>(ssim_lambda);
  if (grad) grad->create(rendered.size(), CV_32FC3);
  const double l1 = sum_over_rows(rendered.rows, [&](int r) {
    const float* x = rendered.ptr<float>(r);
    const float* y = target.image.ptr<float>(r);
    float row = 0;
    for (int i = 0; i < width; ++i) row += std::abs(x[i] - y[i]);
    if (!grad) return static_cast<double>(row);
    float* g = grad->ptr<float>(r);
    for (int i = 0; i < width; ++i) {
      const float d = x[i] - y[i];
      g[i] = static_cast<float>((d > 0) - (d < 0)) * l1_step;
    }
    if (!ssim_grad.empty()) {
      const float* sg = ssim_grad.ptr<float>(r);
      for (int i = 0; i < width; ++i) g[i] -= ssim_scale * sg[i];
    }
    return static_cast<double>(row);
  });
  loss.l1 = l1 / count;
  loss.value = (1 - ssim_lambda) * loss.l1 + ssim_lambda * (1 - loss.ssim);
  return loss;
}

PhotometricLoss photometric_loss(const cv::Mat& rendered, const cv::Mat& target, double ssim_lambda,
                                 cv::Mat* grad) {
  require_same(rendered, target, CV_32FC3, "photometric_loss");
  return photometric_loss(rendered, SsimTarget(target), ssim_lambda, grad);
}

double depth_log_l1_loss(const cv::Mat& rendered, const cv::Mat& target, cv::Mat* grad) {
  require_same(rendered, target, CV_32FC1, "depth_log_l1_loss");
  if (grad) *grad = cv::Mat::zeros(rendered.size(), CV_32FC1);
  const double valid = sum_over_rows(target.rows, [&](int r) {
    const float* d = target.ptr<float>(r);
    int count = 0;
    for (int c = 0; c < target.cols; ++c) count += valid_depth(d[c]);
    return static_cast<double>(count);
  });
  if (valid == 0) return 0;
  const double inv = 1.0 / valid;
  const double sum = sum_over_rows(rendered.rows, [&](int r) {
    double row = 0;
    const float* d_hat = rendered.ptr<float>(r);
    const float* d = target.ptr<float>(r);
    float* g = grad ? grad->ptr<float>(r) : nullptr;
    for (int c = 0; c < rendered.cols; ++c) {
      if (!valid_depth(d[c])) continue;
      const float e = d_hat[c] - d[c];
      row += std::log1p(std::abs(e));
      // d/de log(1 + |e|) = sign(e) / (1 + |e|)
      if (g && e != 0) g[c] = static_cast<float>(inv * (e > 0 ? 1 : -1) / (1 + std::abs(e)));
    }
    return row;
  });
  return sum * inv;
}

namespace {

// normal_cosine_loss's pixels in runs of this many: their terms kept, then added in order.
constexpr int kCosineChunk = 64;
constexpr double kMinNorm2 = 1e-12;  // a usable pixel's rendered normal: |n_hat| >= 1e-6

// |a|^2 of a pixel's three floats, in double.
inline double squared_norm(const float* a) {
  return static_cast<double>(a[0]) * a[0] + static_cast<double>(a[1]) * a[1] +
         static_cast<double>(a[2]) * a[2];
}

// Whether the normal loss uses a pixel: its target normal b is present and its rendered normal's
// squared norm n2 is at least kMinNorm2.
inline bool usable_normal(double n2, const float* b) {
  return (b[0] != 0.f || b[1] != 0.f || b[2] != 0.f) && n2 >= kMinNorm2;
}

// The terms 1 - cos(a, b) of `count` pixels of rendered normals a and target normals b (three
// floats each), 0 where the pixel is not usable (no target, or |a| < 1e-6), and with kGrad their
// gradients times inv into g (0 where not usable). Every pixel is computed and the unusable ones
// selected away, over distinct arrays: a loop GCC vectorises, where the branch per pixel kept it
// scalar (1.4% of the main job's samples).
template <bool kGrad>
void normal_cosine_terms(const float* __restrict a, const float* __restrict b, int count,
                         double inv, double* __restrict terms, float* __restrict g) {
  for (int c = 0; c < count; ++c) {
    const double a0 = a[3 * c], a1 = a[3 * c + 1], a2 = a[3 * c + 2];
    const double n2 = squared_norm(a + 3 * c);
    const bool use = usable_normal(n2, b + 3 * c);
    const double len = std::sqrt(n2);
    const double dot = a0 * b[3 * c] + a1 * b[3 * c + 1] + a2 * b[3 * c + 2];
    const double cosine = dot / len;
    terms[c] = use ? 1 - cosine : 0.0;
    if constexpr (kGrad) {
      // d cos / d a = b / |a| - (a.b) a / |a|^3
      const double k = cosine / (len * len);
      g[3 * c] = use ? static_cast<float>(-(b[3 * c] / len - k * a0) * inv) : 0.f;
      g[3 * c + 1] = use ? static_cast<float>(-(b[3 * c + 1] / len - k * a1) * inv) : 0.f;
      g[3 * c + 2] = use ? static_cast<float>(-(b[3 * c + 2] / len - k * a2) * inv) : 0.f;
    }
  }
}

}  // namespace

double normal_cosine_loss(const cv::Mat& rendered, const cv::Mat& target, cv::Mat* grad) {
  require_same(rendered, target, CV_32FC3, "normal_cosine_loss");
  if (grad) *grad = cv::Mat::zeros(rendered.size(), CV_32FC3);
  // Two passes: count the valid pixels first so the gradient carries the 1/N of the mean.
  const double valid = sum_over_rows(rendered.rows, [&](int r) {
    const float* a = rendered.ptr<float>(r);
    const float* b = target.ptr<float>(r);
    int count = 0;
    for (int c = 0; c < rendered.cols; ++c)
      count += usable_normal(squared_norm(a + 3 * c), b + 3 * c);
    return static_cast<double>(count);
  });
  if (valid == 0) return 0;
  const double inv = 1.0 / valid;
  const double sum = sum_over_rows(rendered.rows, [&](int r) {
    const float* a = rendered.ptr<float>(r);
    const float* b = target.ptr<float>(r);
    float* g = grad ? grad->ptr<float>(r) : nullptr;
    double row = 0;
    for (int c0 = 0; c0 < rendered.cols; c0 += kCosineChunk) {
      const int count = std::min(kCosineChunk, rendered.cols - c0);
      double terms[kCosineChunk];
      if (g)
        normal_cosine_terms<true>(a + 3 * c0, b + 3 * c0, count, inv, terms, g + 3 * c0);
      else
        normal_cosine_terms<false>(a + 3 * c0, b + 3 * c0, count, inv, terms, nullptr);
      for (int c = 0; c < count; ++c) row += terms[c];  // 0 where not usable: the same sum
    }
    return row;
  });
  return sum * inv;
}

namespace {

// Mean over the N Gaussians of a term of each one's three log-scales (log_scales is N x 3).
// term(s, g) returns the Gaussian's term and writes its gradient with respect to s into g (three
// values, zeroed); grad (resized to N x 3) receives the mean's gradient, g / N.
// Parallel over Gaussians in a fixed number of blocks (a serial loop kept the second core idle at
// every step); each block sums its terms in Gaussian order, and the blocks' sums are added in
// block order, so the value does not depend on the thread count.
template <class Term>
double mean_scale_term(const std::vector<float>& log_scales, std::vector<float>* grad, Term term) {
  const size_t n = log_scales.size() / 3;
  if (grad) grad->resize(log_scales.size());
  if (n == 0) return 0;
  constexpr size_t kBlocks = 64;
  const size_t block_size = (n + kBlocks - 1) / kBlocks;
  std::array<double, kBlocks> sums{};
  tbb::parallel_for(size_t(0), kBlocks, [&](size_t b) {
    double sum = 0;
    for (size_t i = b * block_size; i < std::min(n, (b + 1) * block_size); ++i) {
      double g[3] = {0, 0, 0};
      sum += term(&log_scales[i * 3], g);
      for (int k = 0; grad && k < 3; ++k)
        (*grad)[i * 3 + k] = static_cast<float>(g[k] / static_cast<double>(n));
    }
    sums[b] = sum;
  });
  double sum = 0;
  for (const double s : sums) sum += s;
  return sum / static_cast<double>(n);
}

}  // namespace

double flatness_loss(const std::vector<float>& log_scales, std::vector<float>* grad) {
  return mean_scale_term(log_scales, grad, [](const float* s, double* g) {
    const int k = s[0] <= s[1] ? (s[0] <= s[2] ? 0 : 2) : (s[1] <= s[2] ? 1 : 2);
    // d exp(s_k) / d s_k = exp(s_k); the min picks one axis (a subgradient at ties).
    g[k] = std::exp(static_cast<double>(s[k]));
    return g[k];
  });
}

}  // namespace gslift
