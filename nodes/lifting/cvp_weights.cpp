#include "nodes/lifting/cvp_weights.hpp"

#include <cmath>
#include <stdexcept>

namespace gslift {

MaskPixelWeights cvp_weights(const cv::Mat1b& mask, double sigma) {
  if (!(sigma > 0)) throw std::invalid_argument("cvp_weights: sigma must be positive");
  MaskPixelWeights out;
  double cx = 0, cy = 0;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (mask(y, x)) {
        out.pixels.emplace_back(x, y);
        cx += x;
        cy += y;
      }
  if (out.pixels.empty()) return out;
  const double count = static_cast<double>(out.pixels.size());
  cx /= count;
  cy /= count;
  std::vector<double> squared(out.pixels.size());
  double mean_squared = 0;
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    const double dx = out.pixels[i].x - cx, dy = out.pixels[i].y - cy;
    squared[i] = dx * dx + dy * dy;
    mean_squared += squared[i];
  }
  mean_squared /= count;  // RMS radius squared
  out.weights.resize(out.pixels.size());
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    const double r2 = mean_squared > 0 ? squared[i] / mean_squared : 0.0;
    out.weights[i] = std::exp(-r2 / (2 * sigma * sigma)) / count;
  }
  return out;
}

}  // namespace gslift
