#include "nodes/inference/label_inference.hpp"

#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/inference/label_argmax.hpp"
#include "nodes/inference/prototype_kmeans.hpp"
#include "nodes/inference/prototypes.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

FeatureMap render_feature_map(const GaussianModel& model, const View& view) {
  RenderSettings settings;
  settings.rgb = false;
  settings.features = true;
  RenderOutput r = render(model, view.camera, view.pose, settings);
  FeatureMap map;
  map.width = r.width;
  map.height = r.height;
  map.dim = r.feature_dim;
  map.values = std::move(r.features);
  return map;
}

LabelMapSet infer_labels_by_prototypes(const GaussianModel& model, const Capture& capture,
                                       const LabelMapSet& consistent, const std::vector<int>& views,
                                       PrototypeClassifier kind, uint64_t seed,
                                       double min_feature_norm) {
  if (model.feature_dim < 1) throw InputError("inference: the model has no feature channels");
  std::vector<FeatureMap> maps;
  std::vector<cv::Mat1i> labels;
  for (const LabelMap& m : consistent.views) {
    const int v = capture.find_view(m.view);
    if (v < 0)
      throw InputError("inference: label map of view '" + m.view + "' is not in capture '" +
                       capture.name + "'");
    if (capture.views[v].held_out) continue;  // held-out maps are test data
    maps.push_back(render_feature_map(model, capture.views[v]));
    labels.push_back(m.labels);
  }
  if (maps.empty()) throw InputError("inference: no training view has a consistent label map");
  const LabelPrototypes p = label_prototypes(maps, labels);
  Eigen::MatrixXf classifier = p.averaged;
  std::vector<int> ids = p.ids;
  if (kind == PrototypeClassifier::KMeans) {
    classifier = spherical_kmeans(p.per_view, static_cast<int>(p.ids.size()), seed);
    ids.resize(classifier.rows());
    for (size_t c = 0; c < ids.size(); ++c) ids[c] = static_cast<int>(c) + 1;
  }
  const double min_norm = min_feature_norm > 0 ? min_feature_norm * median_feature_norm(maps) : 0;
  LabelMapSet out;
  out.labels = ids.empty() ? 0 : *std::max_element(ids.begin(), ids.end());
  for (const int v : views) {
    const FeatureMap f = render_feature_map(model, capture.views[v]);
    cv::Mat1i view_labels = nearest_prototype_labels(f, classifier, ids);
    if (min_norm > 0) label_faint_features(f, min_norm, view_labels);
    out.views.push_back({capture.views[v].name, view_labels});
  }
  return out;
}

LabelMapSet infer_labels_by_classifier(const GaussianModel& model, const Capture& capture,
                                       const LabelClassifier& c, const std::vector<int>& views) {
  if (model.feature_dim != c.dim)
    throw InputError("inference.classifier: the classifier expects " + std::to_string(c.dim) +
                     " feature channels, the model has " + std::to_string(model.feature_dim));
  const Eigen::Map<const Eigen::MatrixXf> w(c.weights.data(), c.dim, c.classes);  // column = class
  const Eigen::Map<const Eigen::VectorXf> b(c.bias.data(), c.classes);
  std::vector<int> ids(c.classes);
  for (int k = 0; k < c.classes; ++k) ids[k] = k;
  LabelMapSet out;
  out.labels = c.classes - 1;
  for (const int v : views) {
    const FeatureMap f = render_feature_map(model, capture.views[v]);
    std::vector<float> scores(size_t(f.width) * f.height * c.classes);
    tbb::parallel_for(0, f.height, [&](int y) {
      for (int x = 0; x < f.width; ++x)
        Eigen::Map<Eigen::VectorXf>(scores.data() + (size_t(y) * f.width + x) * c.classes,
                                    c.classes) =
            w.transpose() * Eigen::Map<const Eigen::VectorXf>(f.at(x, y), f.dim) + b;
    });
    out.views.push_back({capture.views[v].name, argmax_labels(scores, f.width, f.height, ids)});
  }
  return out;
}

}  // namespace gslift
