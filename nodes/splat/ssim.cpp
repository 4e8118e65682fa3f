#include "nodes/splat/ssim.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace gslift {
namespace {

constexpr double kC1 = 0.01 * 0.01;
constexpr double kC2 = 0.03 * 0.03;
constexpr int kRadius = 5;  // 11 taps
constexpr int kTaps = 2 * kRadius + 1;

// Normalised 1D Gaussian, sigma 1.5 (3DGS's gaussian(11, 1.5)); the 2D window is its outer product.
std::array<float, kTaps> window_taps() {
  std::array<double, kTaps> w{};
  double sum = 0;
  for (int k = 0; k < kTaps; ++k) {
    const double d = k - kRadius;
    w[k] = std::exp(-d * d / (2 * 1.5 * 1.5));
    sum += w[k];
  }
  std::array<float, kTaps> out{};
  for (int k = 0; k < kTaps; ++k) out[k] = static_cast<float>(w[k] / sum);
  return out;
}

void require_ssim_inputs(const cv::Mat& x, const cv::Mat& y) {
  if (x.size() != y.size() || x.type() != y.type() || x.depth() != CV_32F)
    throw std::invalid_argument("ssim: images must be CV_32F of the same size and channels");
}

// Rows [begin, end) of the separable window: per row, the vertical pass into a buffer with kRadius
// zero pixels either side (the zero padding), then the horizontal pass. Tap-outer loops, so both
// passes are contiguous multiply-adds over the row.
void window_rows(const cv::Mat& in, cv::Mat& out, int begin, int end) {
  static const std::array<float, kTaps> w = window_taps();
  const int channels = in.channels(), width = in.cols * channels;
  std::vector<float> buffer((in.cols + 2 * kRadius) * channels, 0.f);
  float* padded = buffer.data() + kRadius * channels;
  for (int r = begin; r < end; ++r) {
    std::fill_n(padded, width, 0.f);
    for (int k = 0; k < kTaps; ++k) {
      const int source = r + k - kRadius;
      if (source < 0 || source >= in.rows) continue;
      const float* src = in.ptr<float>(source);
      const float wk = w[k];
      for (int i = 0; i < width; ++i) padded[i] += wk * src[i];
    }
    float* dst = out.ptr<float>(r);
    std::fill_n(dst, width, 0.f);
    for (int k = 0; k < kTaps; ++k) {
      const float* src = padded + (k - kRadius) * channels;
      const float wk = w[k];
      for (int i = 0; i < width; ++i) dst[i] += wk * src[i];
    }
  }
}

}  // namespace

cv::Mat ssim_window(const cv::Mat& image) {
  cv::Mat out(image.size(), image.type());
  tbb::parallel_for(tbb::blocked_range<int>(0, image.rows, 16), [&](const auto& range) {
    window_rows(image, out, range.begin(), range.end());
  });
  return out;
}

SsimTarget::SsimTarget(const cv::Mat& target)
    : image(target), mean(ssim_window(target)), mean_sq(ssim_window(target.mul(target))) {}

double ssim(const cv::Mat& x, const SsimTarget& target, cv::Mat* grad_x) {
  const cv::Mat& y = target.image;
  require_ssim_inputs(x, y);
  const cv::Mat mu_x = ssim_window(x);
  const cv::Mat e_xx = ssim_window(x.mul(x));
  const cv::Mat e_xy = ssim_window(x.mul(y));

  const int channels = x.channels(), width = x.cols * channels;
  const size_t count = x.total() * channels;
  cv::Mat d_mu, d_exx, d_exy;  // dSSIM/d(windowed means), per pixel
  if (grad_x) {
    d_mu.create(x.size(), x.type());
    d_exx.create(x.size(), x.type());
    d_exy.create(x.size(), x.type());
  }
  const float g = static_cast<float>(1.0 / static_cast<double>(count));
  const float c1 = static_cast<float>(kC1), c2 = static_cast<float>(kC2);
  // Row sums are reduced in a fixed row order (deterministic at any thread count).
  std::vector<double> row_sum(x.rows, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, x.rows, 16), [&](const tbb::blocked_range<int>& rr) {
    std::vector<float> row_ssim(width);
    for (int r = rr.begin(); r < rr.end(); ++r) {
      const float* mx = mu_x.ptr<float>(r);
      const float* my = target.mean.ptr<float>(r);
      const float* xx = e_xx.ptr<float>(r);
      const float* yy = target.mean_sq.ptr<float>(r);
      const float* xy = e_xy.ptr<float>(r);
      float* dmu = grad_x ? d_mu.ptr<float>(r) : nullptr;
      float* dxx = grad_x ? d_exx.ptr<float>(r) : nullptr;
      float* dxy = grad_x ? d_exy.ptr<float>(r) : nullptr;
      // Float arithmetic (as the 3DGS reference in torch float32) so the loop vectorises; the
      // row's sum is accumulated in double afterwards (a double sum inside kept it scalar).
      for (int i = 0; i < width; ++i) {
        // S = A B / (C D), A = 2 mx my + C1, B = 2 sxy + C2, C = mx^2 + my^2 + C1,
        // D = sxx + syy + C2.
        const float a_mx = mx[i], a_my = my[i];
        const float sxx = xx[i] - a_mx * a_mx, syy = yy[i] - a_my * a_my;
        const float sxy = xy[i] - a_mx * a_my;
        const float A = 2 * a_mx * a_my + c1, B = 2 * sxy + c2;
        const float C = a_mx * a_mx + a_my * a_my + c1, D = sxx + syy + c2;
        const float inv_cd = 1.f / (C * D);
        const float s = A * B * inv_cd;
        row_ssim[i] = s;
        if (!dmu) continue;
        const float ds_dsxx = -s / D;
        const float ds_dsxy = 2 * A * inv_cd;
        // mx enters A, C directly and sxx, sxy through -mx^2 and -mx my.
        const float ds_dmx =
            2 * a_my * B * inv_cd - s * 2 * a_mx / C + ds_dsxx * (-2 * a_mx) + ds_dsxy * (-a_my);
        dmu[i] = g * ds_dmx;
        dxx[i] = g * ds_dsxx;
        dxy[i] = g * ds_dsxy;
      }
      double sum = 0;
      for (int i = 0; i < width; ++i) sum += row_ssim[i];
      row_sum[r] = sum;
    }
  });
  if (grad_x) {
    // d/dx of window(x) is window^T = window; of window(x^2) adds 2x; of window(x y) adds y.
    const cv::Mat w_mu = ssim_window(d_mu);
    const cv::Mat w_xx = ssim_window(d_exx);
    const cv::Mat w_xy = ssim_window(d_exy);
    grad_x->create(x.size(), x.type());
    tbb::parallel_for(tbb::blocked_range<int>(0, x.rows, 16), [&](const auto& rows) {
      for (int r = rows.begin(); r < rows.end(); ++r) {
        const float *a = w_mu.ptr<float>(r), *b = w_xx.ptr<float>(r), *c = w_xy.ptr<float>(r);
        const float *px = x.ptr<float>(r), *py = y.ptr<float>(r);
        float* out = grad_x->ptr<float>(r);
        for (int i = 0; i < width; ++i) out[i] = a[i] + 2 * px[i] * b[i] + py[i] * c[i];
      }
    });
  }
  double sum = 0;
  for (double s : row_sum) sum += s;
  return sum / static_cast<double>(count);
}

double ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* grad_x) {
  require_ssim_inputs(x, y);
  return ssim(x, SsimTarget(y), grad_x);
}

}  // namespace gslift
