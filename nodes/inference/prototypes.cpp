#include "nodes/inference/prototypes.hpp"

#include <algorithm>
#include <map>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/inference/label_argmax.hpp"

namespace gslift {

LabelPrototypes label_prototypes(const std::vector<FeatureMap>& maps,
                                 const std::vector<cv::Mat1i>& labels) {
  if (maps.empty() || maps.size() != labels.size())
    throw InputError("inference.prototypes: one label map per training feature map is needed");
  const int dim = maps[0].dim;
  LabelPrototypes out;
  // label -> (sum over views of v_k(t), views)
  std::map<int, std::pair<Eigen::VectorXd, int>> sums;
  std::vector<Eigen::VectorXf> rows;
  for (size_t k = 0; k < maps.size(); ++k) {
    const FeatureMap& f = maps[k];
    const cv::Mat1i& l = labels[k];
    if (l.cols != f.width || l.rows != f.height)
      throw InputError("inference.prototypes: a label map differs in size from its view");
    std::map<int, std::pair<Eigen::VectorXd, int>> view;  // label -> (feature sum, pixels)
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        auto& s = view[l(y, x)];
        if (s.second == 0) s.first = Eigen::VectorXd::Zero(dim);
        s.first += Eigen::Map<const Eigen::VectorXf>(f.at(x, y), dim).cast<double>();
        ++s.second;
      }
    for (const auto& [id, s] : view) {
      const Eigen::VectorXd v = s.first / s.second;  // Eq. 17
      rows.push_back(v.cast<float>());
      out.per_view_ids.push_back(id);
      auto& total = sums[id];
      if (total.second == 0) total.first = Eigen::VectorXd::Zero(dim);
      total.first += v;
      ++total.second;
    }
  }
  out.per_view.resize(static_cast<Eigen::Index>(rows.size()), dim);
  for (size_t r = 0; r < rows.size(); ++r) out.per_view.row(r) = rows[r].transpose();
  out.averaged.resize(static_cast<Eigen::Index>(sums.size()), dim);
  for (const auto& [id, s] : sums) {
    out.averaged.row(out.ids.size()) = (s.first / s.second).cast<float>().transpose();  // Eq. 18
    out.ids.push_back(id);
  }
  return out;
}

cv::Mat1i nearest_prototype_labels(const FeatureMap& map, const Eigen::MatrixXf& prototypes,
                                   const std::vector<int>& ids) {
  if (prototypes.rows() == 0 || prototypes.cols() != map.dim ||
      size_t(prototypes.rows()) != ids.size())
    throw InputError("inference: prototypes do not match the rendered features");
  Eigen::MatrixXf unit = prototypes;
  for (Eigen::Index r = 0; r < unit.rows(); ++r) {
    const float n = unit.row(r).norm();
    if (n > 0) unit.row(r) /= n;
  }
  // cos(v, F) ranks like v_unit . F: |F| is the same for every prototype.
  const size_t rows = ids.size();
  std::vector<float> scores(size_t(map.width) * map.height * rows);
  tbb::parallel_for(0, map.height, [&](int y) {
    for (int x = 0; x < map.width; ++x)
      Eigen::Map<Eigen::VectorXf>(scores.data() + (size_t(y) * map.width + x) * rows, rows) =
          unit * Eigen::Map<const Eigen::VectorXf>(map.at(x, y), map.dim);
  });
  return argmax_labels(scores, map.width, map.height, ids);
}

double median_feature_norm(const std::vector<FeatureMap>& maps) {
  std::vector<float> norms;
  for (const FeatureMap& m : maps)
    for (int y = 0; y < m.height; ++y)
      for (int x = 0; x < m.width; ++x)
        norms.push_back(Eigen::Map<const Eigen::VectorXf>(m.at(x, y), m.dim).norm());
  if (norms.empty()) return 0;
  const auto mid = norms.begin() + norms.size() / 2;  // the upper middle for an even count
  std::nth_element(norms.begin(), mid, norms.end());
  return *mid;
}

size_t label_faint_features(const FeatureMap& map, double min_norm, cv::Mat1i& labels) {
  if (labels.cols != map.width || labels.rows != map.height)
    throw InputError("inference: a label map differs in size from its feature map");
  size_t set = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x)
      if (Eigen::Map<const Eigen::VectorXf>(map.at(x, y), map.dim).norm() < min_norm) {
        labels(y, x) = 0;
        ++set;
      }
  return set;
}

}  // namespace gslift
