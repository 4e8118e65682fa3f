// Structural similarity (Wang et al. 2004) exactly as the 3DGS training code computes it: an 11x11
// Gaussian window (sigma 1.5) applied per channel with zero padding, C1 = 0.01^2, C2 = 0.03^2 for
// images in [0,1], and the SSIM map averaged over every pixel and channel.
#pragma once

#include <opencv2/core.hpp>

namespace gslift {

// The windowed statistics of a fixed target image (its windowed mean and mean of squares), computed
// once per training view instead of at every step.
struct SsimTarget {
  explicit SsimTarget(const cv::Mat& image);  // CV_32F, any channels
  cv::Mat image, mean, mean_sq;
};

// The 3DGS window (11 taps, sigma 1.5, zero padding) applied separably to every channel of a CV_32F
// image: a vertical then a horizontal 11-tap pass, parallel over rows (each output pixel is one
// fixed sum, so the result does not depend on the thread count).
cv::Mat ssim_window(const cv::Mat& image);

// Mean SSIM of two float images of equal size and channel count (CV_32F, any channels).
// When grad_x is given it receives d(mean SSIM)/dx, same size and type as x. The window is
// symmetric and zero-padded, so the adjoint of each windowed mean is the same filter; the
// gradient is the three windowed means' adjoints applied to the per-pixel partials of the SSIM map.
double ssim(const cv::Mat& x, const SsimTarget& y, cv::Mat* grad_x = nullptr);
double ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* grad_x = nullptr);

}  // namespace gslift
