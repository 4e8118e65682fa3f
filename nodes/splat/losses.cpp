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

PhotometricLoss photometric_loss(const cv::Mat& rendered, const cv::Mat& target, double ssim_lambda,
                                 cv::Mat* grad) {
  require_same(rendered, target, CV_32FC3, "photometric_loss");
  PhotometricLoss loss;
  const cv::Mat diff = rendered - target;
  const double count = static_cast<double>(rendered.total() * 3);
  loss.l1 = cv::norm(diff, cv::NORM_L1) / count;
  cv::Mat ssim_grad;
  loss.ssim = ssim(rendered, target, grad && ssim_lambda != 0 ? &ssim_grad : nullptr);
  loss.value = (1 - ssim_lambda) * loss.l1 + ssim_lambda * (1 - loss.ssim);
  if (grad) {
    // d|x|/dx = sign(x); sign(0) = 0 like torch.
    cv::Mat sign = cv::Mat::zeros(diff.size(), diff.type());
    sign.setTo(cv::Scalar::all(1), diff > 0);
    sign.setTo(cv::Scalar::all(-1), diff < 0);
    *grad = sign * ((1 - ssim_lambda) / count);
    if (ssim_lambda != 0) *grad -= ssim_lambda * ssim_grad;
  }
  return loss;
}

double depth_log_l1_loss(const cv::Mat& rendered, const cv::Mat& target, cv::Mat* grad) {
  require_same(rendered, target, CV_32FC1, "depth_log_l1_loss");
  if (grad) *grad = cv::Mat::zeros(rendered.size(), CV_32FC1);
  double sum = 0;
  size_t valid = 0;
  for (int r = 0; r < rendered.rows; ++r)
    for (int c = 0; c < rendered.cols; ++c)
      if (valid_depth(target.at<float>(r, c))) ++valid;
  if (valid == 0) return 0;
  const double inv = 1.0 / static_cast<double>(valid);
  for (int r = 0; r < rendered.rows; ++r) {
    const float* d_hat = rendered.ptr<float>(r);
    const float* d = target.ptr<float>(r);
    for (int c = 0; c < rendered.cols; ++c) {
      if (!valid_depth(d[c])) continue;
      const double e = static_cast<double>(d_hat[c]) - d[c];
      sum += std::log1p(std::abs(e));
      // d/de log(1 + |e|) = sign(e) / (1 + |e|)
      if (grad && e != 0)
        grad->ptr<float>(r)[c] = static_cast<float>(inv * (e > 0 ? 1 : -1) / (1 + std::abs(e)));
    }
  }
  return sum * inv;
}

double normal_cosine_loss(const cv::Mat& rendered, const cv::Mat& target, cv::Mat* grad) {
  require_same(rendered, target, CV_32FC3, "normal_cosine_loss");
  if (grad) *grad = cv::Mat::zeros(rendered.size(), CV_32FC3);
  constexpr double kMinNorm = 1e-6;
  // Two passes: count the valid pixels first so the gradient carries the 1/N of the mean.
  auto usable = [&](const cv::Vec3f& n_hat, const cv::Vec3f& n) {
    return (n[0] != 0 || n[1] != 0 || n[2] != 0) && cv::norm(n_hat) >= kMinNorm;
  };
  size_t valid = 0;
  for (int r = 0; r < rendered.rows; ++r)
    for (int c = 0; c < rendered.cols; ++c)
      if (usable(rendered.at<cv::Vec3f>(r, c), target.at<cv::Vec3f>(r, c))) ++valid;
  if (valid == 0) return 0;
  const double inv = 1.0 / static_cast<double>(valid);
  double sum = 0;
  for (int r = 0; r < rendered.rows; ++r) {
    for (int c = 0; c < rendered.cols; ++c) {
      const cv::Vec3f& n_hat = rendered.at<cv::Vec3f>(r, c);
      const cv::Vec3f& n = target.at<cv::Vec3f>(r, c);
      if (!usable(n_hat, n)) continue;
      const cv::Vec3d a(n_hat), b(n);
      const double len = cv::norm(a);
      const double cosine = a.dot(b) / len;
      sum += 1 - cosine;
      if (grad) {
        // d cos / d a = b / |a| - (a.b) a / |a|^3
        const cv::Vec3d g = -(b / len - (cosine / (len * len)) * a) * inv;
        grad->at<cv::Vec3f>(r, c) = cv::Vec3f(g);
      }
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
