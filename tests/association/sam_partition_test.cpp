#include "nodes/association/sam_partition.hpp"

#include <catch2/catch.hpp>

using namespace gslift;

namespace {
Mask box(int x, int y, int w, int h, float score, int granularity = 0) {
  Mask m;
  m.pixels = cv::Mat1b::zeros(10, 10);
  m.pixels(cv::Rect(x, y, w, h)).setTo(255);
  m.score = score;
  m.granularity = granularity;
  return m;
}
}  // namespace

// Painted in ascending score: C (0.5) first, then A (0.7), then B (0.9) over both. A is 4x4 = 16
// pixels of which B (4x4 at (2,2)) hides 4: 12/16 visible, kept. C (2x2 at (3,3)) lies inside B:
// 0 visible, dropped. The part mask is at another granularity and ignored. Kept ids renumbered
// in painting order: A -> 1, B -> 2.
TEST_CASE("sam_partition: score order, visibility ratio, renumbering") {
  ViewMasks v;
  v.masks = {box(0, 0, 4, 4, 0.7f), box(2, 2, 4, 4, 0.9f), box(3, 3, 2, 2, 0.5f),
             box(8, 8, 2, 2, 1.f, 1)};
  const cv::Mat1i p = sam_partition(v, 0, {10, 10});
  CHECK(p(0, 0) == 1);
  CHECK(p(3, 1) == 1);
  CHECK(p(2, 2) == 2);
  CHECK(p(4, 4) == 2);
  CHECK(p(9, 9) == 0);
  CHECK(cv::countNonZero(p == 1) == 12);
  CHECK(cv::countNonZero(p == 2) == 16);
  // At 80% required visibility A (75%) is dropped too: B alone, id 1.
  const cv::Mat1i strict = sam_partition(v, 0, {10, 10}, 0.8);
  CHECK(strict(0, 0) == 0);
  CHECK(strict(2, 2) == 1);
}
