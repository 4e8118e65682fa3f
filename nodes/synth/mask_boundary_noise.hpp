// The imprecise boundaries of SAM masks: the boundary of a binary mask is displaced by a smooth
// random field, so the error is locally coherent (bulges and dents) rather than salt-and-pepper.
#pragma once

#include <opencv2/core.hpp>

#include "nodes/synth/stream_purpose.hpp"

namespace gslift::synth {

// Returns {p : sd(p) + amplitude_px * n(p) > 0}, with sd the signed distance to the boundary of
// `mask` (positive inside) and n a standard-normal field interpolated from a 8-pixel lattice.
// amplitude_px = 0 returns a copy. Only the mask's neighbourhood is touched (cost ~ mask size).
cv::Mat1b perturb_mask_boundary(const cv::Mat1b& mask, double amplitude_px, RandomStream& rng);

}  // namespace gslift::synth
