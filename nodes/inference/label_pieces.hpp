// Small connected pieces of a label map, absorbed by the labels around them.
//
// [decision, measured in docs/protosaga.md] Gaga's evaluation counts every label present anywhere
// in a test view as a predicted label (precision = hits / predicted labels), and a novel view's
// per-pixel argmax scatters small islands of a label over the regions of others: Gaussians seen by
// few training pixels, the borders between two instances. Pieces are judged by their own size,
// whatever label they carry, so a small object that is one coherent piece stays (a rule on a
// label's total area in the view, measured before, also dropped small whole objects and lost mIoU
// for its precision: docs/protosaga.md).
// The same step is a param of every label-inference node, so Gaga and Proto-SaGa are compared with
// it on equal terms.
#pragma once

#include <cstddef>

#include <opencv2/core.hpp>

namespace gslift {

// Pieces: 8-connected pixels of one label (label 0 included). Every piece smaller than min_pixels
// gives its pixels to the nearest pixel of a kept piece (a breadth-first fill from the kept pieces,
// 4-connected, in raster order: ties go to the neighbour reached first, so the result does not
// depend on threads). Returns the pixels of the small pieces, all relabelled; a map where no piece
// reaches min_pixels is left as it is (0).
size_t absorb_small_pieces(cv::Mat1i& labels, int min_pixels);

}  // namespace gslift
