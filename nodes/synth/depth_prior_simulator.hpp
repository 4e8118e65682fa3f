// Simulated depth prior of a feed-forward MVS model (VGGT-like): exact depth with relative noise
// (half a smooth low-frequency scale error, half per-pixel noise) and blob-shaped holes.
#pragma once

#include <opencv2/core.hpp>

#include "nodes/synth/stream_purpose.hpp"

namespace gslift::synth {

// gt_depth: CV_32F metres, 0 = invalid. Returns CV_32F metres, 0 = invalid. The noise has
// standard deviation relative_noise * depth; holes cover about hole_fraction of the pixels.
cv::Mat1f simulate_depth_prior(const cv::Mat1f& gt_depth, double relative_noise,
                               double hole_fraction, RandomStream& rng);

}  // namespace gslift::synth
