// Novel-view instance labels from the lifted features (Proto-SaGa §3.3, Table 4), three ways
// behind one output (a LabelMapSet of the requested views):
//  - prototypes (Eq. 17-19): per-label mean rendered features of the training views, averaged
//    over views, argmax cosine;
//  - kmeans: the per-view prototypes clustered, k = number of labels, argmax cosine to a centre
//    (cluster ids, not bank ids: evaluation matches them one to one anyway);
//  - classifier: Gaga's trained 1x1 classifier, argmax of W F + b.
#pragma once

#include <cstdint>
#include <vector>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/feature_map.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/label_maps.hpp"

namespace gslift {

// F(p) of the model's features seen from a view (Proto-SaGa Eq. 5).
FeatureMap render_feature_map(const GaussianModel& model, const View& view);

enum class PrototypeClassifier { Averaged, KMeans };

// Prototypes from the training views of `consistent`, answered in capture views `views`; pixels
// whose rendered feature is shorter than min_feature_norm x the training views' median length
// labelled 0 (label_faint_features). Throws InputError when the model has no features or no
// training view has a consistent map.
LabelMapSet infer_labels_by_prototypes(const GaussianModel& model, const Capture& capture,
                                       const LabelMapSet& consistent, const std::vector<int>& views,
                                       PrototypeClassifier kind, uint64_t seed,
                                       double min_feature_norm = 0);

// argmax_c (W F(p) + b)_c in capture views `views`.
LabelMapSet infer_labels_by_classifier(const GaussianModel& model, const Capture& capture,
                                       const LabelClassifier& classifier,
                                       const std::vector<int>& views);

}  // namespace gslift
