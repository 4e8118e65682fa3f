// How well a set of automatic masks (SAM's, masks.auto's, masks.geometry's) covers the
// ground-truth instances: per instance of each view, the best IoU of any mask of the view, averaged
// over the instances (the "mean best IoU" of segment-proposal evaluation, e.g. the average best
// overlap of Uijlings et al., IJCV 2013), for each granularity alone and for all together. A mask
// set is judged by what a click or a lifting stage could pick from it, so each instance takes its
// best mask; over-segmentation costs masks, not score (masks per view is reported beside it).
#pragma once

#include <vector>

#include "nodes/scene/masks.hpp"

namespace gslift {

struct MaskCoverage {
  int granularity = -1;       // -1 = the masks of every granularity
  int instances = 0;          // ground-truth masks scored
  double mean_best_iou = 0;   // percent
  double masks_per_view = 0;  // of this granularity, over the scored views
};

// One row for all granularities (first), then one per granularity the masks have, ascending.
// Scored views are those both sets have. Throws InputError when they share no view, or the shared
// views have no ground-truth mask, or a mask differs in size from its view's truth.
std::vector<MaskCoverage> mask_coverage(const MaskSet& masks, const MaskSet& truth);

}  // namespace gslift
