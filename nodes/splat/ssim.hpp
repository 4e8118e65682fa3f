// Structural similarity (Wang et al. 2004) exactly as the 3DGS training code computes it: an 11x11
// Gaussian window (sigma 1.5) applied per channel with zero padding, C1 = 0.01^2, C2 = 0.03^2 for
// images in [0,1], and the SSIM map averaged over every pixel and channel.
#pragma once

#include <opencv2/core.hpp>

namespace gslift {

// Mean SSIM of two float images of equal size and channel count (CV_32F, any channels).
// When grad_x is given it receives d(mean SSIM)/dx, same size and type as x. The window is
// symmetric and zero-padded, so the adjoint of each windowed mean is the same filter; the
// gradient is the three windowed means' adjoints applied to the per-pixel partials of the SSIM map.
double ssim(const cv::Mat& x, const cv::Mat& y, cv::Mat* grad_x = nullptr);

}  // namespace gslift
