#include "nodes/synth/depth_prior_simulator.hpp"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace gslift::synth {

cv::Mat1f simulate_depth_prior(const cv::Mat1f& gt_depth, double relative_noise,
                               double hole_fraction, RandomStream& rng) {
  const int w = gt_depth.cols, h = gt_depth.rows;
  // Smooth field on a 32-pixel lattice, bilinearly interpolated (unit variance at lattice
  // points, slightly less between them).
  constexpr int kCell = 32;
  cv::Mat1f lattice(h / kCell + 2, w / kCell + 2);
  for (auto& v : lattice) v = static_cast<float>(rng.normal());
  cv::Mat1f smooth;
  cv::resize(lattice, smooth, cv::Size(lattice.cols * kCell, lattice.rows * kCell), 0, 0,
             cv::INTER_LINEAR);
  const double a = relative_noise * std::sqrt(0.5);
  cv::Mat1f out(h, w, 0.f);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float d = gt_depth(y, x);
      if (d <= 0) continue;
      const double e = a * (smooth(y, x) + rng.normal());
      out(y, x) = static_cast<float>(d * std::max(0.05, 1.0 + e));
    }
  }
  // Holes: discs of random radius until the target fraction of the image is covered.
  cv::Mat1b hole(h, w, uchar(0));
  const double target = hole_fraction * w * h;
  const int max_radius = std::max(2, std::min(w, h) / 12);
  for (int guard = 0; cv::countNonZero(hole) < target && guard < 10000; ++guard) {
    cv::circle(hole, cv::Point(rng.below(w), rng.below(h)), 1 + rng.below(max_radius),
               cv::Scalar(255), cv::FILLED);
  }
  out.setTo(0.f, hole);
  return out;
}

}  // namespace gslift::synth
