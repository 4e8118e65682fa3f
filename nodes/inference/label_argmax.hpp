// The last step of every novel-view label rule (prototypes, K-means centres, Gaga's classifier):
// per pixel the candidate with the highest score. Small pieces of the result are absorbed
// afterwards (label_pieces.hpp).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace gslift {

// scores: width x height x ids.size() row-major (per pixel the score of each candidate). Ties keep
// the lower candidate.
cv::Mat1i argmax_labels(const std::vector<float>& scores, int width, int height,
                        const std::vector<int>& ids);

}  // namespace gslift
