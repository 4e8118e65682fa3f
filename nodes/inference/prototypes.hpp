// Proto-SaGa §3.3, prototype-based segmentation (Eq. 17-19): no classifier is trained on the
// consistent masks; the features rendered at the training views are averaged per consistent
// label, per view (Eq. 17) and then over the views that contain the label (Eq. 18), and a novel
// view's pixel takes the label of the prototype with the highest cosine (Eq. 19; tau does not
// change the argmax). Label 0 (pixels no SAM mask covered) gets a prototype like any other: Gaga's
// classifier has a class 0 too, and its evaluation scores label 0 as a class.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nodes/scene/feature_map.hpp"

namespace gslift {

struct LabelPrototypes {
  std::vector<int> ids;      // the labels present in some training view, ascending
  Eigen::MatrixXf averaged;  // ids.size() x dim: v(t) (Eq. 18)
  // Eq. 17 of every (view, label present there): v_k(t), and its label.
  Eigen::MatrixXf per_view;
  std::vector<int> per_view_ids;
};

// maps[k] and labels[k] (CV_32SC1, the map's size) of the training views.
LabelPrototypes label_prototypes(const std::vector<FeatureMap>& maps,
                                 const std::vector<cv::Mat1i>& labels);

// Eq. 19: per pixel, ids[argmax_r cos(prototypes.row(r), F(p))]. Ties keep the lower row.
cv::Mat1i nearest_prototype_labels(const FeatureMap& map, const Eigen::MatrixXf& prototypes,
                                   const std::vector<int>& ids);

// The median length of the rendered feature over every pixel of `maps`, the upper of the two
// middle values for an even count (0 when they are empty).
double median_feature_norm(const std::vector<FeatureMap>& maps);

// Label 0 (no SAM mask) where the rendered feature is shorter than min_norm; returns how many
// pixels were set. Eq. 19's cosine ignores a feature's length, but a short one is a pixel the
// trained features barely reach (open space at silhouettes, Gaussians no training pixel trained,
// which keep their small random start), and its direction picks a label at random.
size_t label_faint_features(const FeatureMap& map, double min_norm, cv::Mat1i& labels);

}  // namespace gslift
