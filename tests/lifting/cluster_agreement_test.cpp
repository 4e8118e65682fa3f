#include "nodes/lifting/cluster_agreement.hpp"

#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("adjusted Rand index of a hand-computed contingency table") {
  // a = {0,0,0,1,1,1}, b = {0,0,1,1,2,2}: contingency cells 2,1,1,2 -> index = 1 + 0 + 0 + 1 = 2;
  // row pairs 3 + 3 = 6; column pairs 1 + 1 + 1 = 3; total pairs 15; expected 6 * 3 / 15 = 1.2;
  // max (6 + 3) / 2 = 4.5; ARI = (2 - 1.2) / (4.5 - 1.2) = 0.8 / 3.3.
  const std::vector<int> a{0, 0, 0, 1, 1, 1};
  const std::vector<int> b{0, 0, 1, 1, 2, 2};
  CHECK(adjusted_rand_index(a, b) == Approx(0.8 / 3.3).epsilon(1e-12));
  CHECK(adjusted_rand_index(b, a) == Approx(0.8 / 3.3).epsilon(1e-12));
}

TEST_CASE("adjusted Rand index is 1 under relabelling and for trivial partitions") {
  CHECK(adjusted_rand_index({0, 0, 1, 1, -1}, {5, 5, 2, 2, -1}) == Approx(1.0));
  CHECK(adjusted_rand_index({3, 3, 3}, {1, 1, 1}) == 1.0);
  // Independent-looking: a splits halves, b alternates -> index 0, expected 2*2/6 ... below 0.
  CHECK(adjusted_rand_index({0, 0, 1, 1}, {0, 1, 0, 1}) == Approx(-0.5));
  CHECK_THROWS_AS(adjusted_rand_index({0}, {0, 1}), std::invalid_argument);
}

TEST_CASE("same_partition accepts renamings only, noise fixed") {
  CHECK(same_partition({0, 0, 1, -1}, {7, 7, 3, -1}));
  CHECK_FALSE(same_partition({0, 0, 1, -1}, {7, 7, 7, -1}));  // merged
  CHECK_FALSE(same_partition({0, 0, 1, 1}, {0, 1, 2, 2}));    // split
  CHECK_FALSE(same_partition({0, 0, 1, -1}, {7, 7, -1, 3}));  // noise moved
}
