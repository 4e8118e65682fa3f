// Gaga's mask/get_raw_mask.py (method-anchors §1.1 step 2): one view's SAM automatic masks painted
// into one id image, the "inconsistent mask" M_k that Proto-SaGa's view classifier (Eq. 7) and the
// memory bank (Eq. 9) read. Masks are painted in ascending score order, so a higher-score mask
// overwrites a lower one where they overlap and the result is a partition; a mask keeps its id
// only when more than min_visible of its pixels remain visible, and the kept ids are renumbered
// 1..K in painting order (0 = no mask). Ids are 32-bit: Gaga's uint8 image caps a view at 255.
#pragma once

#include <opencv2/core.hpp>

#include "nodes/scene/masks.hpp"

namespace gslift {

// The masks of `masks` at SAM granularity `granularity` (0 whole, 1 part; masks of other levels
// are skipped), painted as above into a CV_32SC1 map of their size. Ties in score keep the
// masks' order (stable sort). Returns an all-zero map of size `size` when no mask is at that level.
cv::Mat1i sam_partition(const ViewMasks& masks, int granularity, cv::Size size,
                        double min_visible = 0.1);

}  // namespace gslift
