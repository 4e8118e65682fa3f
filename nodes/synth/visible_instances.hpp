// Which ground-truth instances a view shows, with their pixel boxes: the truth that the simulated
// upstream models (VLM, SAM) start from.
#pragma once

#include <map>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/boxes.hpp"

namespace gslift::synth {

struct VisibleInstance {
  int instance = 0;
  int class_id = 0;
  int pixels = 0;  // visible pixel count
  Box box;         // tight XYXY pixel box of the visible pixels (pixel-corner convention)
};

// Instances covering at least min_fraction of the image, in increasing instance id.
std::vector<VisibleInstance> visible_instances(const cv::Mat& instance_map,
                                               const std::map<int, int>& instance_class,
                                               double min_fraction);

}  // namespace gslift::synth
