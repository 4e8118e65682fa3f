// Simulated SAM prompted with a box: the mask of the instance the box covers best, with boundary
// noise and occasional leaks into a neighbour inside the box; for a box that covers no instance
// well (a hallucinated box), a plausible wrong blob that follows the region under the box.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/boxes.hpp"
#include "nodes/synth/stream_purpose.hpp"
#include "nodes/synth/synth_knobs.hpp"

namespace gslift::synth {

struct SamBoxMask {
  cv::Mat1b mask;       // full image, 255 inside
  int instance = 0;     // the instance the box covers best, 0 = none (wrong blob)
  int leaked_into = 0;  // the neighbour the mask leaked into, 0 = no leak
};

// Coverage score of instance i by the box: n_in^2 / (n_i * box_area), n_in its pixels inside
// the box, n_i all its pixels: 1 for a tight box around a fully visible instance, small both for
// a box that cuts the instance and for a box much larger than it. Below this the box is "empty".
constexpr double kMinBoxCoverage = 0.1;

// Pixel count per id (index = id) of a CV_32S label map with ids >= 0.
std::vector<int> count_labels(const cv::Mat& ids, const cv::Rect& area);

// `instance_pixels` = count_labels(instance_map, whole image), computed once per view.
SamBoxMask simulate_sam_box(const Box& box, const cv::Mat& instance_map,
                            const std::vector<int>& instance_pixels, const SynthKnobs& knobs,
                            RandomStream& rng);

}  // namespace gslift::synth
