// What the fusion stages read from the capture for a semantic view: its capture view, and the
// depth they back-project (the capture's depth prior, the paper's RGB-D sensor).
#pragma once

#include <opencv2/core.hpp>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/semantic_maps.hpp"

namespace gslift {

// The capture view a semantic view names; throws InputError naming `stage` when it has none.
const View& capture_view(const Capture& capture, const SemanticView& view, const char* stage);

// The view's depth prior (CV_32F metres); throws InputError naming `stage` when it has none.
cv::Mat1f depth_prior(const View& view, const char* stage);

}  // namespace gslift
