#include "nodes/synth/mask_boundary_noise.hpp"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace gslift::synth {

cv::Mat1b perturb_mask_boundary(const cv::Mat1b& mask, double amplitude_px, RandomStream& rng) {
  cv::Mat1b out = mask.clone();
  if (amplitude_px <= 0 || cv::countNonZero(mask) == 0) return out;
  // Work in the mask's bounding box grown by the largest plausible displacement (3 sigma).
  const int margin = static_cast<int>(std::ceil(3 * amplitude_px)) + 2;
  const cv::Rect bbox = cv::boundingRect(mask);
  const cv::Rect roi = cv::Rect(bbox.x - margin, bbox.y - margin, bbox.width + 2 * margin,
                                bbox.height + 2 * margin) &
                       cv::Rect(0, 0, mask.cols, mask.rows);
  const cv::Mat1b inside = mask(roi) > 0;
  cv::Mat1f d_in, d_out;
  cv::distanceTransform(inside, d_in, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::distanceTransform(~inside, d_out, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  constexpr int kCell = 8;
  cv::Mat1f lattice(roi.height / kCell + 2, roi.width / kCell + 2);
  for (auto& v : lattice) v = static_cast<float>(rng.normal());
  cv::Mat1f field;
  cv::resize(lattice, field, cv::Size(lattice.cols * kCell, lattice.rows * kCell), 0, 0,
             cv::INTER_LINEAR);
  for (int y = 0; y < roi.height; ++y) {
    for (int x = 0; x < roi.width; ++x) {
      // Pixel centres at distance d from the other side lie d - 0.5 from the boundary.
      const float sd = inside(y, x) ? d_in(y, x) - 0.5f : 0.5f - d_out(y, x);
      out(roi.y + y, roi.x + x) = sd + amplitude_px * field(y, x) > 0 ? 255 : 0;
    }
  }
  return out;
}

}  // namespace gslift::synth
