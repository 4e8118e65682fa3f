// The last step of every novel-view label rule (prototypes, K-means centres, Gaga's classifier):
// per pixel the candidate with the highest score, optionally without the labels that would cover
// only a sliver of the view.
//
// Minimum label area [decision, measured in docs/protosaga.md]: Gaga's evaluation counts every
// label that appears anywhere in a test view as a predicted label (precision = hits / predicted
// labels), so a label shown only as a few speckle pixels of poorly observed Gaussians costs
// precision without any chance of a match. With min_area > 0 the candidates whose argmax area in
// the view is below min_area x the view's pixels are dropped and their pixels take the best
// remaining candidate. One pass suffices: the kept labels only gain pixels.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace gslift {

// scores: width x height x ids.size() row-major (per pixel the score of each candidate). Ties keep
// the lower candidate. min_area in [0, 1]; 0 = plain argmax. At least the largest label is kept.
cv::Mat1i argmax_labels(const std::vector<float>& scores, int width, int height,
                        const std::vector<int>& ids, double min_area);

}  // namespace gslift
