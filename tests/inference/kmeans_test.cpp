// K-means on hand-built feature rows: known clusters, and the same answer for the same seed.
#include "nodes/inference/kmeans.hpp"

#include <algorithm>

#include "tests/test_support.hpp"

using namespace gslift;

namespace {
// Three tight groups in 2D around (0,0), (10,0), (0,10): four points each, offsets +-0.1.
std::vector<float> three_groups() {
  std::vector<float> rows;
  const float centres[3][2] = {{0, 0}, {10, 0}, {0, 10}};
  const float offsets[4][2] = {{0.1f, 0}, {-0.1f, 0}, {0, 0.1f}, {0, -0.1f}};
  for (const auto& c : centres)
    for (const auto& o : offsets) rows.insert(rows.end(), {c[0] + o[0], c[1] + o[1]});
  return rows;
}
}  // namespace

TEST_CASE("k-means finds well-separated groups and their means") {
  const KMeansResult r = kmeans(three_groups(), 2, 3, 7);
  REQUIRE(r.k == 3);
  for (int g = 0; g < 3; ++g)  // the four rows of a group share a label
    for (int i = 1; i < 4; ++i) CHECK(r.labels[4 * g + i] == r.labels[4 * g]);
  CHECK(r.labels[0] != r.labels[4]);
  CHECK(r.labels[4] != r.labels[8]);
  CHECK(r.labels[0] != r.labels[8]);
  std::vector<std::pair<float, float>> centres;
  for (int c = 0; c < 3; ++c) centres.emplace_back(r.centres[2 * c], r.centres[2 * c + 1]);
  std::sort(centres.begin(), centres.end());
  CHECK(centres[0].first == Approx(0).margin(1e-6));
  CHECK(centres[0].second == Approx(0).margin(1e-6));
  CHECK(centres[1].second == Approx(10));
  CHECK(centres[2].first == Approx(10));
}

TEST_CASE("k-means is deterministic for a seed and caps k at the distinct rows") {
  std::vector<float> rows;
  for (int i = 0; i < 200; ++i) rows.push_back(static_cast<float>((i * 37) % 101) / 7.f);
  const KMeansResult a = kmeans(rows, 1, 5, 3), b = kmeans(rows, 1, 5, 3);
  CHECK(a.centres == b.centres);
  CHECK(a.labels == b.labels);
  // Two distinct rows: two clusters however many were asked for.
  const KMeansResult two = kmeans({1.f, 1.f, 2.f, 2.f, 1.f}, 1, 5, 0);
  CHECK(two.k == 2);
  CHECK_THROWS_AS(kmeans({}, 1, 5, 0), std::invalid_argument);
}
