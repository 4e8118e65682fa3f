// The synthetic GrabCut scene both boxes tests use: a 120x100 textured background and a disc at
// its centre, so that the answer (the disc) is known.
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "base/random.hpp"

namespace gslift::test {

// 120x100 background of random 6x6 colour patches (greens and greys).
inline cv::Mat3b textured_background(uint32_t seed) {
  RandomStream rng(stream_seed(seed, "background"));
  cv::Mat3b image(100, 120);
  for (int y = 0; y < 100; y += 6)
    for (int x = 0; x < 120; x += 6) {
      const int g = 40 + rng.below(161);
      image(cv::Rect(x, y, 6, 6) & cv::Rect(0, 0, 120, 100)).setTo(cv::Vec3b(g / 2, g, g / 2));
    }
  return image;
}

// A filled disc of `radius` at (60, 50), as a 120x100 mask.
inline cv::Mat1b disc(int radius = 22) {
  cv::Mat1b m = cv::Mat1b::zeros(100, 120);
  cv::circle(m, {60, 50}, radius, 255, cv::FILLED);
  return m;
}

// IoU of two masks (0 when both are empty).
inline double iou(const cv::Mat1b& a, const cv::Mat1b& b) {
  const int inter = cv::countNonZero(a & b), uni = cv::countNonZero(a | b);
  return uni == 0 ? 0.0 : double(inter) / uni;
}

}  // namespace gslift::test
