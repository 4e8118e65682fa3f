// Ground truth | render | instances for a view scored by instance (Gaga, Proto-SaGa): the picture
// `gslift report` shows after the metrics (issue 32). The predicted labels are coloured as the
// ground-truth instance the Hungarian matching paired them with, so matching colours mean a
// matched instance; unmatched predictions are grey.
#pragma once

#include <map>
#include <string>

#include <opencv2/core.hpp>

namespace gslift {

// truth and predicted: CV_32SC1 instance ids (0 = none), the render's size; pred_to_gt: each
// matched predicted id's ground-truth id. An empty picture when the sizes differ.
cv::Mat3b instance_comparison_picture(const cv::Mat1i& truth, const cv::Mat3b& render,
                                      const cv::Mat1i& predicted,
                                      const std::map<int, int>& pred_to_gt,
                                      const std::string& title);

}  // namespace gslift
