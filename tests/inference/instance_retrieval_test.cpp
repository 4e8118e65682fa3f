// Relevancy and selection rules against hand-computed values on orthonormal embeddings.
#include "nodes/inference/instance_retrieval.hpp"

#include <cmath>

#include "tests/test_support.hpp"

using namespace gslift;

namespace {
Eigen::VectorXf unit(int i, int n = 4) {
  return Eigen::VectorXf::Unit(n, i);
}
}  // namespace

TEST_CASE("relevancy is the minimum pairwise softmax against the negatives") {
  Eigen::MatrixXf semantics(3, 4);
  semantics.row(0) = unit(0).transpose();                                  // the query itself
  semantics.row(1) = unit(1).transpose();                                  // a negative
  semantics.row(2) = (0.6f * unit(0) + 0.8f * unit(2)).transpose() * 2.f;  // unnormalised
  Eigen::MatrixXf negatives(2, 4);
  negatives.row(0) = unit(1).transpose();
  negatives.row(1) = unit(2).transpose();
  const Eigen::VectorXf r = instance_relevancy(semantics, unit(0), negatives, 10.f);
  // Row 0: cos_q = 1, cos_neg = 0, 0 -> 1 / (1 + e^-10).
  CHECK(r[0] == Approx(1.0 / (1.0 + std::exp(-10.0))));
  // Row 1: cos_q = 0, against negative 0 cos = 1 -> 1 / (1 + e^10) (the minimum).
  CHECK(r[1] == Approx(1.0 / (1.0 + std::exp(10.0))).epsilon(1e-4));
  // Row 2: cos_q = 0.6, cos with negative 1 = 0.8 -> 1 / (1 + e^2).
  CHECK(r[2] == Approx(1.0 / (1.0 + std::exp(2.0))));
  // Without negatives nothing is ruled out.
  CHECK(instance_relevancy(semantics, unit(0), Eigen::MatrixXf(0, 4)).isOnes());
  CHECK(relevancy_selection(r, 0.5f) == std::vector<int>{0});
}

TEST_CASE("closed set: each instance answers its most similar query if it beats the negatives") {
  Eigen::MatrixXf semantics(4, 4);
  semantics.row(0) = unit(0).transpose();
  semantics.row(1) = (0.8f * unit(1) + 0.6f * unit(0)).transpose();  // closer to query 1
  semantics.row(2) = unit(1).transpose();
  semantics.row(3) = (0.3f * unit(0) + 0.954f * unit(3)).transpose();  // nearest query 0, but a
                                                                       // negative is nearer
  Eigen::MatrixXf vocabulary(2, 4);
  vocabulary.row(0) = unit(0).transpose();
  vocabulary.row(1) = unit(1).transpose();
  Eigen::MatrixXf negatives(1, 4);
  negatives.row(0) = unit(3).transpose();
  const auto selected = closed_set_selection(semantics, vocabulary, negatives);
  REQUIRE(selected.size() == 2);
  CHECK(selected[0] == std::vector<int>{0});
  CHECK(selected[1] == std::vector<int>{1, 2});
  // Without the negative, instance 3 goes to query 0.
  CHECK(closed_set_selection(semantics, vocabulary, Eigen::MatrixXf(0, 4))[0] ==
        std::vector<int>{0, 3});
}
