// LangOR Eq. 4 (cross-view pixel lifting): the sampling weight of each pixel p of a mask M,
//   w(p) = (1 / |M|) exp(-||p - c_M||^2 / (2 sigma^2)),
// with c_M the mask centroid. sigma = 0.5 (0.7 in the paper's ablation) only makes sense in
// normalised units, so ||p - c_M|| is measured in units of the mask's RMS radius
// sqrt(mean_p ||p - c_M||^2) [decision; the paper gives no unit]: the same sigma then concentrates
// samples equally on small and large masks, and the 1/|M| factor gives every mask a similar total
// weight when all masks of all views are sampled jointly (AliasSampler).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace gslift {

struct MaskPixelWeights {
  std::vector<cv::Point> pixels;  // the mask's pixels (x, y), row-major order
  std::vector<double> weights;    // Eq. 4 weight of each pixel
};

// mask: 8-bit, non-zero inside. sigma > 0 (std::invalid_argument otherwise). An empty mask gives
// empty vectors; a one-pixel mask (RMS radius 0) gives that pixel the weight 1.
MaskPixelWeights cvp_weights(const cv::Mat1b& mask, double sigma);

}  // namespace gslift
