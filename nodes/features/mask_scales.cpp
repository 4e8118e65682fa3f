#include "nodes/features/mask_scales.hpp"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace gslift {

std::vector<float> mask_scales(const std::vector<float>& depth, const Camera& cam,
                               const std::vector<cv::Mat1b>& masks, bool swap_axes) {
  std::vector<float> out;
  out.reserve(masks.size());
  for (const cv::Mat1b& m : masks) {
    // 3x3 box sum of the 0/1 mask, zero padded; >= 5 of the 9 pixels keeps the centre.
    cv::Mat1f sum;
    cv::boxFilter(m / 255, sum, CV_32F, cv::Size(3, 3), cv::Point(-1, -1), false,
                  cv::BORDER_CONSTANT);
    double n = 0, s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    for (int y = 0; y < m.rows; ++y)
      for (int x = 0; x < m.cols; ++x) {
        const float d = depth[size_t(y) * m.cols + x];
        if (sum(y, x) < 4.5f || d <= 0) continue;
        const double a = swap_axes ? y : x, b = swap_axes ? x : y;
        const double p[3] = {(a - cam.cx) * d / cam.fx, (b - cam.cy) * d / cam.fy, d};
        ++n;
        for (int k = 0; k < 3; ++k) s[k] += p[k], s2[k] += p[k] * p[k];
      }
    double norm2 = 0;
    for (int k = 0; k < 3 && n >= 2; ++k) {
      const double var = std::max(0.0, (s2[k] - s[k] * s[k] / n) / (n - 1));
      norm2 += 4 * var;  // (2 std)^2
    }
    out.push_back(static_cast<float>(std::sqrt(norm2)));
  }
  return out;
}

}  // namespace gslift
