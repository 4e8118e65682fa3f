// Simulated SAM automatic mask generator for one view: whole-object masks, except that an
// instance is split into its parts (head/torso/legs, device parts) or merged with its most
// adjacent neighbour at configured rates, plus small spurious fragments. Draws are independent per
// view, so the segmentation is inconsistent across views, as Proto-SaGa and Gaga assume. With
// two granularities, part masks are added at level 1 for SAGA's multi-scale masks.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/synth/stream_purpose.hpp"
#include "nodes/synth/synth_knobs.hpp"

namespace gslift::synth {

struct AutoMask {
  enum class Kind { Whole, Part, Merged, Fragment };
  cv::Mat1b mask;  // full image, 255 inside
  Kind kind = Kind::Whole;
  int granularity = 0;         // 0 whole, 1 part (SAGA)
  std::vector<int> instances;  // the ground-truth instances it was made from (empty: fragment)
  float predicted_iou = 1.f;
  float stability_score = 1.f;
};

// instance_map and part_map as rendered (CV_32S). Masks smaller than min_area_fraction of the
// image are dropped, like SAM's min_mask_region_area.
std::vector<AutoMask> simulate_sam_auto(const cv::Mat& instance_map, const cv::Mat& part_map,
                                        const SynthKnobs& knobs, RandomStream& rng,
                                        double min_area_fraction = 3e-4);

}  // namespace gslift::synth
