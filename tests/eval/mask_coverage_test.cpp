// Mean best IoU of automatic masks per ground-truth instance, on hand-counted masks.
#include "nodes/eval/mask_coverage.hpp"

#include "base/errors.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

Mask rect_mask(cv::Rect r, int granularity = 0) {
  Mask m;
  m.pixels = cv::Mat1b::zeros(10, 10);
  m.pixels(r).setTo(255);
  m.granularity = granularity;
  return m;
}

}  // namespace

TEST_CASE("mask coverage: per instance the best mask's IoU, per granularity and over all") {
  // Truth: a 4x4 square A and a 2x5 bar B in view v; view w has truth but no masks (not scored).
  MaskSet truth;
  truth.views = {{"v", {rect_mask({0, 0, 4, 4}), rect_mask({6, 0, 2, 5})}},
                 {"w", {rect_mask({0, 0, 10, 10})}}};
  // Granularity 0: A exactly, and a 4x5 block holding B (IoU 10 / 20). Granularity 1: half of A
  // (8 / 16) and B exactly.
  MaskSet masks;
  masks.views = {{"v",
                  {rect_mask({0, 0, 4, 4}, 0), rect_mask({6, 0, 4, 5}, 0),
                   rect_mask({0, 0, 2, 4}, 1), rect_mask({6, 0, 2, 5}, 1)}}};
  const std::vector<MaskCoverage> rows = mask_coverage(masks, truth);
  REQUIRE(rows.size() == 3);
  CHECK(rows[0].granularity == -1);
  CHECK(rows[0].instances == 2);
  CHECK(rows[0].mean_best_iou == Approx(100.0));  // each instance has an exact mask
  CHECK(rows[0].masks_per_view == Approx(4.0));
  CHECK(rows[1].granularity == 0);
  CHECK(rows[1].mean_best_iou == Approx(100.0 * (1.0 + 0.5) / 2));
  CHECK(rows[1].masks_per_view == Approx(2.0));
  CHECK(rows[2].granularity == 1);
  CHECK(rows[2].mean_best_iou == Approx(100.0 * (0.5 + 1.0) / 2));
}

TEST_CASE("mask coverage: nothing to compare is an error") {
  MaskSet truth, masks;
  truth.views = {{"v", {rect_mask({0, 0, 4, 4})}}};
  masks.views = {{"u", {rect_mask({0, 0, 4, 4})}}};
  CHECK_THROWS_WITH(mask_coverage(masks, truth), Catch::Contains("share no view"));
  masks.views[0].view = "v";
  masks.views[0].masks[0].pixels = cv::Mat1b::zeros(5, 5);
  CHECK_THROWS_WITH(mask_coverage(masks, truth), Catch::Contains("5x5"));
}
