#include "nodes/inference/instance_retrieval.hpp"

#include <algorithm>
#include <cmath>

namespace gslift {
namespace {

// Cosine of every row of `rows` with `v` (0 where either is zero).
Eigen::VectorXf row_cosines(const Eigen::MatrixXf& rows, const Eigen::VectorXf& v) {
  Eigen::VectorXf c = rows * v;
  const float vn = v.norm();
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    const float d = rows.row(i).norm() * vn;
    c[i] = d > 0.f ? c[i] / d : 0.f;
  }
  return c;
}

}  // namespace

std::vector<std::string> canonical_negatives() {
  return {"object", "things", "stuff", "texture"};
}

Eigen::VectorXf instance_relevancy(const Eigen::MatrixXf& semantics, const Eigen::VectorXf& query,
                                   const Eigen::MatrixXf& negatives, float scale) {
  const Eigen::VectorXf cq = row_cosines(semantics, query);
  Eigen::VectorXf relevancy = Eigen::VectorXf::Ones(semantics.rows());
  for (Eigen::Index j = 0; j < negatives.rows(); ++j) {
    const Eigen::VectorXf cn = row_cosines(semantics, negatives.row(j).transpose());
    for (Eigen::Index i = 0; i < semantics.rows(); ++i)
      relevancy[i] = std::min(relevancy[i], 1.f / (1.f + std::exp(scale * (cn[i] - cq[i]))));
  }
  return relevancy;
}

std::vector<std::vector<int>> closed_set_selection(const Eigen::MatrixXf& semantics,
                                                   const Eigen::MatrixXf& vocabulary,
                                                   const Eigen::MatrixXf& negatives, float scale) {
  std::vector<std::vector<int>> selected(vocabulary.rows());
  if (vocabulary.rows() == 0) return selected;
  Eigen::MatrixXf cos(semantics.rows(), vocabulary.rows());
  for (Eigen::Index q = 0; q < vocabulary.rows(); ++q)
    cos.col(q) = row_cosines(semantics, vocabulary.row(q).transpose());
  for (Eigen::Index i = 0; i < semantics.rows(); ++i) {
    Eigen::Index best = 0;
    cos.row(i).maxCoeff(&best);  // Eigen returns the first maximum
    const Eigen::VectorXf r =
        instance_relevancy(semantics.row(i), vocabulary.row(best).transpose(), negatives, scale);
    if (r[0] > 0.5f) selected[best].push_back(static_cast<int>(i));
  }
  return selected;
}

std::vector<int> relevancy_selection(const Eigen::VectorXf& relevancy, float threshold) {
  std::vector<int> selected;
  for (Eigen::Index i = 0; i < relevancy.size(); ++i)
    if (relevancy[i] > threshold) selected.push_back(static_cast<int>(i));
  return selected;
}

}  // namespace gslift
