// The segments of a label image as masks: what every automatic mask generator here ends with
// (masks.auto's graph segmentation, masks.geometry's plane and crease regions).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/masks.hpp"

namespace gslift {

// Appends one mask per label id of `labels` (CV_32S; negative = no segment) whose area is in
// [min_area, max_area] pixels, at `granularity`, in ascending id order.
void append_label_segments(const cv::Mat& labels, int granularity, int min_area, int max_area,
                           std::vector<Mask>& out);

}  // namespace gslift
