// Which Gaussians a 2D object mask rules out: those whose centre projects into the mask's view,
// in front of the camera and inside the frame, at a pixel outside the mask. SAGA (paper 001
// §4.5) validates the selected Gaussians by the prompt's 2D mask before it grows them; a Gaussian
// behind the camera or outside the frame says nothing against the mask and is not ruled out.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/capture.hpp"

namespace gslift {

// means: N x 3 centres (row-major); mask: view-sized, nonzero = the object. Per Gaussian 1 when
// ruled out. Throws InputError when the mask's size is not the view's.
std::vector<char> centres_outside_mask(const std::vector<float>& means, const View& view,
                                       const cv::Mat1b& mask);

}  // namespace gslift
