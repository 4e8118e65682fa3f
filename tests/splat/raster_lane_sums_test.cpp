// The lane sums of the blending loops (nodes/splat/raster_state.hpp): lane_sums over up to 16
// vectors at once must be lane_sum of each, bit for bit, or the rasterizer's gradients would
// depend on how many sums an entry takes at once.
#include <cstring>
#include <random>

#include "nodes/splat/raster_state.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("raster: lane_sums adds each vector's lanes in lane_sum's order", "[splat][raster]") {
  // 0 + 1 + ... + 15, and a case whose float sum depends on the order: lane_sum's first level
  // adds lanes x and x + 8, (2^24, 1) and (-2^24, 3), where 2^24 + 1 rounds to 2^24 (to even) and
  // -2^24 + 3 is exact, so the sum is 3; left to right it would be 2^24 - 2^24 + 1 + 3 = 4.
  alignas(64) float counting[kLanes], ordered[kLanes] = {};
  for (int x = 0; x < kLanes; ++x) counting[x] = float(x);
  ordered[0] = 16777216.f;
  ordered[8] = 1.f;
  ordered[1] = -16777216.f;
  ordered[9] = 3.f;
  const LaneVector hand[2] = {load_lanes(counting), load_lanes(ordered)};
  float hand_sums[2];
  lane_sums(hand, 2, hand_sums);
  CHECK(hand_sums[0] == 120.f);
  CHECK(hand_sums[1] == 3.f);
  CHECK(lane_sum(ordered) == 3.f);

  // Every count of vectors, lanes of mixed magnitudes and signs: equal bits, and nothing written
  // past out[n - 1].
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> mantissa(-1.f, 1.f);
  std::uniform_int_distribution<int> exponent(-20, 20);
  for (int n = 1; n <= kLanes; ++n) {
    alignas(64) float lanes[kLanes][kLanes];
    LaneVector vectors[kLanes];
    for (int i = 0; i < n; ++i) {
      for (int x = 0; x < kLanes; ++x) lanes[i][x] = std::ldexp(mantissa(rng), exponent(rng));
      vectors[i] = load_lanes(lanes[i]);
    }
    float out[kLanes + 1];
    std::fill(std::begin(out), std::end(out), -7.f);
    lane_sums(vectors, n, out);
    for (int i = 0; i < n; ++i) {
      const float expected = lane_sum(lanes[i]);
      CHECK(std::memcmp(&out[i], &expected, sizeof expected) == 0);
    }
    for (int i = n; i <= kLanes; ++i) CHECK(out[i] == -7.f);
  }
}
