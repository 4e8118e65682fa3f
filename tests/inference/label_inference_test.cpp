#include <cmath>

#include <catch2/catch.hpp>

#include "nodes/inference/label_argmax.hpp"
#include "nodes/inference/label_pieces.hpp"
#include "nodes/inference/prototype_kmeans.hpp"
#include "nodes/inference/prototypes.hpp"

using namespace gslift;

namespace {
FeatureMap map_of(int width, std::vector<float> values) {
  FeatureMap m;
  m.width = width;
  m.height = 1;
  m.dim = 2;
  m.values.assign(values.begin(), values.end());
  return m;
}
}  // namespace

// View A: labels [1 1 2], features (2,0) (0,2) (0,1): v_A(1) = (1,1), v_A(2) = (0,1).
// View B: labels [1 2 2], features (3,1) (1,0) (1,2): v_B(1) = (3,1), v_B(2) = (1,1).
// Eq. 18: v(1) = (2,1), v(2) = (0.5,1). A novel pixel (1,0): cos 2/sqrt5 = 0.89 against
// 0.5/sqrt1.25 = 0.45 -> label 1; (0,1): 0.45 against 0.89 -> label 2.
TEST_CASE("label_prototypes and nearest_prototype_labels: Eq. 17-19 by hand") {
  const std::vector<FeatureMap> maps{map_of(3, {2, 0, 0, 2, 0, 1}), map_of(3, {3, 1, 1, 0, 1, 2})};
  const std::vector<cv::Mat1i> labels{(cv::Mat1i(1, 3) << 1, 1, 2), (cv::Mat1i(1, 3) << 1, 2, 2)};
  const LabelPrototypes p = label_prototypes(maps, labels);
  REQUIRE(p.ids == std::vector<int>{1, 2});
  CHECK(p.averaged(0, 0) == Approx(2.f));
  CHECK(p.averaged(0, 1) == Approx(1.f));
  CHECK(p.averaged(1, 0) == Approx(0.5f));
  CHECK(p.averaged(1, 1) == Approx(1.f));
  REQUIRE(p.per_view.rows() == 4);
  CHECK(p.per_view_ids == std::vector<int>{1, 2, 1, 2});
  CHECK(p.per_view(2, 0) == Approx(3.f));
  const cv::Mat1i out =
      nearest_prototype_labels(map_of(3, {1, 0, 0, 1, 1, 1.2f}), p.averaged, p.ids);
  CHECK(out(0, 0) == 1);
  CHECK(out(0, 1) == 2);
  // (1, 1.2): cos with (2,1) = 3.2/(sqrt5 sqrt2.44) = 0.916, with (0.5,1) = 1.7/(sqrt1.25
  // sqrt2.44) = 0.973 -> label 2.
  CHECK(out(0, 2) == 2);
}

// The maps above have feature lengths 2, 2, 1 and sqrt10, 1, sqrt5: sorted 1 1 2 2 2.24 3.16, the
// upper middle 2. A novel view of lengths 0.1, 1, 1.56 (features (0.06,0.08) (1,0) (1,1.2)) at
// 0.6 x 2 = 1.2 keeps only its last label; the pixels below it take label 0.
TEST_CASE("label_faint_features: label 0 below a fraction of the training views' median length") {
  const std::vector<FeatureMap> maps{map_of(3, {2, 0, 0, 2, 0, 1}), map_of(3, {3, 1, 1, 0, 1, 2})};
  CHECK(median_feature_norm(maps) == Approx(2.0));
  CHECK(median_feature_norm({map_of(3, {2, 0, 0, 2, 0, 1})}) == Approx(2.0));  // 1 2 2
  CHECK(median_feature_norm({}) == 0.0);
  const FeatureMap novel = map_of(3, {0.06f, 0.08f, 1, 0, 1, 1.2f});
  cv::Mat1i labels = (cv::Mat1i(1, 3) << 1, 2, 2);
  CHECK(label_faint_features(novel, 0.6 * median_feature_norm(maps), labels) == 2);
  CHECK(labels(0, 0) == 0);
  CHECK(labels(0, 1) == 0);
  CHECK(labels(0, 2) == 2);
  labels = (cv::Mat1i(1, 3) << 1, 2, 2);
  CHECK(label_faint_features(novel, 0.0, labels) == 0);  // off
  CHECK(labels(0, 0) == 1);
  cv::Mat1i wrong(1, 2, 1);
  CHECK_THROWS(label_faint_features(novel, 1.0, wrong));
}

// Six pixels (3 x 2), candidates ids 1, 2, 3: per pixel the highest score's id; a tie (the
// second pixel's 0.5 against 0.5) keeps the lower candidate.
TEST_CASE("argmax_labels: the best candidate per pixel, ties to the lower") {
  const std::vector<float> scores = {1, 0, 0,    0.5f, 0.5f, 0,    0, 1, 0,
                                     0, 1, 0.5f, 0.2f, 0.6f, 0.9f, 0, 1, 0};
  const std::vector<int> ids = {1, 2, 3};
  const cv::Mat1i out = argmax_labels(scores, 3, 2, ids);
  CHECK(out.cols == 3);
  CHECK(std::vector<int>(out.begin(), out.end()) == std::vector<int>{1, 1, 2, 2, 3, 2});
  CHECK_THROWS(argmax_labels(scores, 3, 1, ids));  // scores for six pixels, a view of three
}

// Two tight bundles of directions: K-means with k = 2 finds one centre in each, whatever the
// seed; with k larger than the points it keeps one centre per point.
TEST_CASE("spherical_kmeans: separates two bundles of directions") {
  Eigen::MatrixXf x(6, 2);
  x << 1, 0.05f, 2, -0.1f, 3, 0.1f, 0.05f, 1, -0.1f, 2, 0.1f, 3;
  for (uint64_t seed = 0; seed < 5; ++seed) {
    const Eigen::MatrixXf c = spherical_kmeans(x, 2, seed);
    REQUIRE(c.rows() == 2);
    const bool first_is_x = c(0, 0) > c(0, 1);
    const int ix = first_is_x ? 0 : 1, iy = 1 - ix;
    CHECK(c(ix, 0) > 0.99f);
    CHECK(c(iy, 1) > 0.99f);
    CHECK(c.row(ix).norm() == Approx(1.f));
  }
  CHECK(spherical_kmeans(x, 10, 0).rows() == 6);
}

// A 4 x 5 map of label 1 with a 2-pixel piece of label 3 in a corner, a lone pixel of 2 inside and
// a 3-pixel piece of 4 connected only diagonally. min 3 pixels: the pieces of 3 and 2 take label 1
// around them; the diagonal piece of 4 counts as one piece of 3 and stays.
TEST_CASE("absorb_small_pieces: pieces below the minimum take the labels around them") {
  auto flat = [](const cv::Mat1i& m) { return std::vector<int>(m.begin(), m.end()); };
  cv::Mat1i m = (cv::Mat1i(4, 5) << 3, 3, 1, 1, 4,  //
                 1, 1, 1, 4, 1,                     //
                 1, 2, 4, 1, 1,                     //
                 1, 1, 1, 1, 1);
  CHECK(absorb_small_pieces(m, 3) == 3);
  CHECK(flat(m) == std::vector<int>{1, 1, 1, 1, 4, 1, 1, 1, 4, 1, 1, 1, 4, 1, 1, 1, 1, 1, 1, 1});
  // A pixel between two kept pieces takes the one the raster-order fill reaches first (the left).
  cv::Mat1i row = (cv::Mat1i(1, 5) << 1, 1, 7, 2, 2);
  CHECK(absorb_small_pieces(row, 2) == 1);
  CHECK(flat(row) == std::vector<int>{1, 1, 1, 2, 2});
  // A two-pixel piece between two kept ones is filled from both sides, a pixel from each.
  row = (cv::Mat1i(1, 8) << 1, 1, 1, 7, 7, 2, 2, 2);
  CHECK(absorb_small_pieces(row, 3) == 2);
  CHECK(flat(row) == std::vector<int>{1, 1, 1, 1, 2, 2, 2, 2});
  // No piece reaches the minimum: nothing to fill from, the map stays; 0 or 1 = off.
  cv::Mat1i specks = (cv::Mat1i(1, 3) << 1, 2, 3);
  CHECK(absorb_small_pieces(specks, 2) == 0);
  CHECK(flat(specks) == std::vector<int>{1, 2, 3});
  CHECK(absorb_small_pieces(row, 1) == 0);
}
