#include "nodes/splat/losses.hpp"

#include <cmath>
#include <stdexcept>

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
  double l1 = 0;
  for (int r = 0; r < rendered.rows; ++r) {
    const float* x = rendered.ptr<float>(r);
    const float* y = target.image.ptr<float>(r);
    float* g = grad ? grad->ptr<float>(r) : nullptr;
    const float* sg = ssim_grad.empty() ? nullptr : ssim_grad.ptr<float>(r);
    float row = 0;
    for (int i = 0; i < width; ++i) {
      const float d = x[i] - y[i];
      row += std::abs(d);
      if (!g) continue;
      g[i] = (d > 0 ? l1_step : d < 0 ? -l1_step : 0.f) - (sg ? ssim_scale * sg[i] : 0.f);
    }
    l1 += row;
  }
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
  size_t valid = 0;
  for (int r = 0; r < target.rows; ++r) {
    const float* d = target.ptr<float>(r);
    for (int c = 0; c < target.cols; ++c) valid += valid_depth(d[c]);
  }
  if (valid == 0) return 0;
  const double inv = 1.0 / static_cast<double>(valid);
  double sum = 0;
  for (int r = 0; r < rendered.rows; ++r) {
    const float* d_hat = rendered.ptr<float>(r);
    const float* d = target.ptr<float>(r);
    float* g = grad ? grad->ptr<float>(r) : nullptr;
    for (int c = 0; c < rendered.cols; ++c) {
      if (!valid_depth(d[c])) continue;
      const float e = d_hat[c] - d[c];
      sum += std::log1p(std::abs(e));
      // d/de log(1 + |e|) = sign(e) / (1 + |e|)
      if (g && e != 0) g[c] = static_cast<float>(inv * (e > 0 ? 1 : -1) / (1 + std::abs(e)));
    }
  }
  return sum * inv;
}

double normal_cosine_loss(const cv::Mat& rendered, const cv::Mat& target, cv::Mat* grad) {
  require_same(rendered, target, CV_32FC3, "normal_cosine_loss");
  if (grad) *grad = cv::Mat::zeros(rendered.size(), CV_32FC3);
  constexpr double kMinNorm2 = 1e-12;  // |n_hat| >= 1e-6
  auto usable = [&](const float* a, const float* b) {
    return (b[0] != 0 || b[1] != 0 || b[2] != 0) && static_cast<double>(a[0]) * a[0] +
                                                            static_cast<double>(a[1]) * a[1] +
                                                            static_cast<double>(a[2]) * a[2] >=
                                                        kMinNorm2;
  };
  // Two passes: count the valid pixels first so the gradient carries the 1/N of the mean.
  size_t valid = 0;
  for (int r = 0; r < rendered.rows; ++r) {
    const float* a = rendered.ptr<float>(r);
    const float* b = target.ptr<float>(r);
    for (int c = 0; c < rendered.cols; ++c) valid += usable(a + 3 * c, b + 3 * c);
  }
  if (valid == 0) return 0;
  const double inv = 1.0 / static_cast<double>(valid);
  double sum = 0;
  for (int r = 0; r < rendered.rows; ++r) {
    const float* a_row = rendered.ptr<float>(r);
    const float* b_row = target.ptr<float>(r);
    float* g_row = grad ? grad->ptr<float>(r) : nullptr;
    for (int c = 0; c < rendered.cols; ++c) {
      const float* a = a_row + 3 * c;
      const float* b = b_row + 3 * c;
      if (!usable(a, b)) continue;
      const double len =
          std::sqrt(static_cast<double>(a[0]) * a[0] + static_cast<double>(a[1]) * a[1] +
                    static_cast<double>(a[2]) * a[2]);
      const double dot = static_cast<double>(a[0]) * b[0] + static_cast<double>(a[1]) * b[1] +
                         static_cast<double>(a[2]) * b[2];
      const double cosine = dot / len;
      sum += 1 - cosine;
      if (!g_row) continue;
      // d cos / d a = b / |a| - (a.b) a / |a|^3
      for (int k = 0; k < 3; ++k)
        g_row[3 * c + k] = static_cast<float>(-(b[k] / len - (cosine / (len * len)) * a[k]) * inv);
    }
  }
  return sum * inv;
}

double flatness_loss(const std::vector<float>& log_scales, std::vector<float>* grad) {
  const size_t n = log_scales.size() / 3;
  if (grad) grad->assign(log_scales.size(), 0.f);
  if (n == 0) return 0;
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* s = &log_scales[i * 3];
    const int k = s[0] <= s[1] ? (s[0] <= s[2] ? 0 : 2) : (s[1] <= s[2] ? 1 : 2);
    const double scale = std::exp(static_cast<double>(s[k]));
    sum += scale;
    // d exp(s_k) / d s_k = exp(s_k); the min picks one axis (a subgradient at ties).
    if (grad) (*grad)[i * 3 + k] = static_cast<float>(scale / static_cast<double>(n));
  }
  return sum / static_cast<double>(n);
}

}  // namespace gslift
