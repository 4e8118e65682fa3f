// The training views of a LabelMapSet with their frozen-geometry PixelRows: what the classifier
// objectives (Proto-SaGa's per-view classifiers on raw SAM ids, Gaga's lift on consistent ids)
// train on, through train_pixel_features.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/random.hpp"
#include "nodes/features/pixel_feature_training.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/label_maps.hpp"

namespace gslift {

struct LabelledViews {
  std::vector<int> capture_views;  // index into the capture
  std::vector<int> label_views;    // index into the LabelMapSet
  std::vector<cv::Mat1i> labels;   // continuous, the view's size
  std::vector<PixelRows> rows;
  size_t bytes() const;
};

// The maps of `maps` that name training views of `capture` (held-out maps are test data and
// skipped), in LabelMapSet order, without rows. Throws InputError (prefixed by `node`) when a map
// names a view the capture lacks or differs from its camera in size, or when no training view is
// left.
LabelledViews labelled_training_views(const Capture& capture, const LabelMapSet& maps,
                                      const std::string& node);

// labelled_training_views with the PixelRows of `model` at each view (weights >= min_weight).
LabelledViews render_labelled_views(const GaussianModel& model, const Capture& capture,
                                    const LabelMapSet& maps, double min_weight,
                                    const std::string& node);

// n pixels of a view of `total` pixels drawn uniformly with replacement, appended to `pixels`.
void sample_uniform_pixels(int n, size_t total, RandomStream& rng, std::vector<uint32_t>& pixels);

}  // namespace gslift
