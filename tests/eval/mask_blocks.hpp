// Mask fixtures shared by the eval tests.
#pragma once

#include <opencv2/core.hpp>

namespace gslift::test {

// A rows x cols mask that is 255 inside r and 0 elsewhere.
inline cv::Mat1b block(int rows, int cols, cv::Rect r) {
  cv::Mat1b m = cv::Mat1b::zeros(rows, cols);
  m(r).setTo(255);
  return m;
}

}  // namespace gslift::test
