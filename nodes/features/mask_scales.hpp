// The 3D size of each automatic mask, which SAGA's scale-gated features are conditioned on (the
// public v2 code's get_scale.py; ../shared/reference/method-anchors.md §1.3 "Mask scale"): the
// view's depth is rendered from the trained 3DGS and back-projected through the pinhole, each mask
// is eroded (3x3 box sum of the mask >= 5, zero outside the image), and the mask's scale is
// |2 std(points under the eroded mask)| (per-axis standard deviation, n - 1 in the denominator as
// torch.std; the norm of the 3-vector).
//
// The code's quirk: it back-projects x from the ROW index and y from the column index against
// (cx, fx) and (cy, fy). With swap_axes (default, as the code) gslift does the same; without it,
// x = (column - cx) d / fx, y = (row - cy) d / fy. The std is shift-invariant, so the swap only
// matters through the depth-weighted offset (cx - cy) d and the fx / fy ratio: scales shift
// slightly, their order barely (docs/saga.md).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"

namespace gslift {

// depth: H x W camera-space depths (row-major, as the rasterizer renders them; pixels with
// depth <= 0 are left out). One scale per mask, 0 for a mask with fewer than 2 depth points left
// after erosion.
std::vector<float> mask_scales(const std::vector<float>& depth, const Camera& camera,
                               const std::vector<cv::Mat1b>& masks, bool swap_axes = true);

}  // namespace gslift
