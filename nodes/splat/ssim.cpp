#include "nodes/splat/ssim.hpp"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace gslift {
namespace {

constexpr double kC1 = 0.01 * 0.01;
constexpr double kC2 = 0.03 * 0.03;

// The windowed mean: 11x11 Gaussian, sigma 1.5, zero padding (3DGS's conv2d with padding 5).
cv::Mat window_mean(const cv::Mat& m) {
  cv::Mat out;
  cv::GaussianBlur(m, out, cv::Size(11, 11), 1.5, 1.5, cv::BORDER_CONSTANT);
  return out;
}

}  // namespace

double ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* grad_x) {
  if (x.size() != y.size() || x.type() != y.type() || x.depth() != CV_32F)
    throw std::invalid_argument("ssim: images must be CV_32F of the same size and channels");
  const cv::Mat mu_x = window_mean(x);
  const cv::Mat mu_y = window_mean(y);
  const cv::Mat e_xx = window_mean(x.mul(x));
  const cv::Mat e_yy = window_mean(y.mul(y));
  const cv::Mat e_xy = window_mean(x.mul(y));

  const int channels = x.channels();
  const size_t count = x.total() * channels;
  cv::Mat d_mu, d_exx, d_exy;  // dSSIM/d(windowed means), per pixel
  if (grad_x) {
    d_mu.create(x.size(), x.type());
    d_exx.create(x.size(), x.type());
    d_exy.create(x.size(), x.type());
  }
  double sum = 0;
  for (int r = 0; r < x.rows; ++r) {
    const float* mx = mu_x.ptr<float>(r);
    const float* my = mu_y.ptr<float>(r);
    const float* xx = e_xx.ptr<float>(r);
    const float* yy = e_yy.ptr<float>(r);
    const float* xy = e_xy.ptr<float>(r);
    for (int i = 0; i < x.cols * channels; ++i) {
      // S = A B / (C D), A = 2 mx my + C1, B = 2 sxy + C2, C = mx^2 + my^2 + C1, D = sxx + syy +
      // C2.
      const double a_mx = mx[i], a_my = my[i];
      const double sxx = xx[i] - a_mx * a_mx, syy = yy[i] - a_my * a_my;
      const double sxy = xy[i] - a_mx * a_my;
      const double A = 2 * a_mx * a_my + kC1, B = 2 * sxy + kC2;
      const double C = a_mx * a_mx + a_my * a_my + kC1, D = sxx + syy + kC2;
      const double s = A * B / (C * D);
      sum += s;
      if (!grad_x) continue;
      const double g = 1.0 / static_cast<double>(count);
      const double ds_dsxx = -s / D;
      const double ds_dsxy = 2 * A / (C * D);
      // mx enters A, C directly and sxx, sxy through -mx^2 and -mx my.
      const double ds_dmx =
          2 * a_my * B / (C * D) - s * 2 * a_mx / C + ds_dsxx * (-2 * a_mx) + ds_dsxy * (-a_my);
      d_mu.ptr<float>(r)[i] = static_cast<float>(g * ds_dmx);
      d_exx.ptr<float>(r)[i] = static_cast<float>(g * ds_dsxx);
      d_exy.ptr<float>(r)[i] = static_cast<float>(g * ds_dsxy);
    }
  }
  if (grad_x) {
    // d/dx of window(x) is window^T = window; of window(x^2) adds 2x; of window(x y) adds y.
    const cv::Mat w_mu = window_mean(d_mu);
    const cv::Mat w_xx = window_mean(d_exx);
    const cv::Mat w_xy = window_mean(d_exy);
    *grad_x = w_mu + 2 * x.mul(w_xx) + y.mul(w_xy);
  }
  return sum / static_cast<double>(count);
}

}  // namespace gslift
