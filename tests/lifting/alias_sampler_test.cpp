#include "nodes/lifting/alias_sampler.hpp"

#include <numeric>

#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("alias sampler frequencies follow the weights (chi-square)") {
  const std::vector<double> weights{1, 2, 3, 4, 0.5, 9.5};
  const AliasSampler sampler(weights);
  const int64_t draws = 200000;
  std::vector<double> counts(weights.size(), 0);
  for (const int64_t i : sampler.sample(draws, 42)) counts[i] += 1;
  const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  double chi2 = 0;
  for (size_t i = 0; i < weights.size(); ++i) {
    const double expected = draws * weights[i] / total;
    chi2 += (counts[i] - expected) * (counts[i] - expected) / expected;
  }
  // 5 degrees of freedom: P(chi2 > 20.5) = 0.001.
  CHECK(chi2 < 20.5);
}

TEST_CASE("alias sampler never draws zero weights, and a single weight always") {
  const AliasSampler sampler({0, 3, 0, 1, 0});
  for (const int64_t i : sampler.sample(20000, 7)) {
    CHECK(i != 0);
    CHECK(i != 2);
    CHECK(i != 4);
  }
  const AliasSampler one({0, 0, 2.5});
  for (const int64_t i : one.sample(1000, 1)) CHECK(i == 2);
  CHECK(AliasSampler({7}).sample(10, 3) == std::vector<int64_t>(10, 0));
}

TEST_CASE("alias sampler is deterministic for a seed and rejects bad weights") {
  const AliasSampler sampler({1, 1, 1, 1});
  CHECK(sampler.sample(100, 5) == sampler.sample(100, 5));
  CHECK(sampler.sample(100, 5) != sampler.sample(100, 6));
  CHECK_THROWS_AS(AliasSampler({0, 0}), std::invalid_argument);
  CHECK_THROWS_AS(AliasSampler({1, -1}), std::invalid_argument);
  CHECK_THROWS_AS(AliasSampler({}), std::invalid_argument);
}
