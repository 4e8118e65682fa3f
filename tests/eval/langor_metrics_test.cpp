// The LangOR metrics on hand-computed masks and relevancy maps.
#include "nodes/eval/langor_metrics.hpp"

#include "tests/eval/mask_blocks.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::block;

TEST_CASE("mask counts and IoU") {
  const cv::Mat1b pred = block(4, 4, {0, 0, 2, 2});  // 4 px
  const cv::Mat1b gt = block(4, 4, {1, 0, 3, 2});    // 6 px, 2 shared
  const MaskCounts c = compare_masks(pred, gt);
  CHECK(c.intersection == 2);
  CHECK(c.uni == 8);
  CHECK(c.gt == 6);
  CHECK(c.pred == 4);
  CHECK(iou(c) == Approx(0.25));
  CHECK(iou(compare_masks(cv::Mat1b::zeros(2, 2), cv::Mat1b::zeros(2, 2))) == 1.0);
  CHECK_THROWS_AS(compare_masks(pred, cv::Mat1b::zeros(3, 4)), std::invalid_argument);
}

TEST_CASE("localisation: plain argmax in the mask, LangSplat's box-filtered argmax in the box") {
  cv::Mat1f rel = cv::Mat1f::zeros(20, 20);
  rel(2, 2) = 1.f;                    // a single hot pixel outside the object
  rel(10, 10) = 1.f;                  // ties go to the first pixel in row-major order
  rel(cv::Rect(8, 8, 6, 6)) += 0.6f;  // a broad plateau on the object
  const cv::Mat1b gt = block(20, 20, {8, 8, 6, 6});
  CHECK(argmax(rel) == cv::Point(10, 10));  // 1.6 beats 1.0
  CHECK(localised_in_mask(rel, gt));
  rel(10, 10) = 0.6f;
  CHECK(argmax(rel) == cv::Point(2, 2));
  CHECK_FALSE(localised_in_mask(rel, gt));
  CHECK_FALSE(localised_in_box(rel, gt, 1));  // no filter: the hot pixel wins
  CHECK(localised_in_box(rel, gt, 3));        // 3x3 mean: 1/9 < 0.6 on the plateau
  // The box variant accepts the GT's bounding box, not only its pixels.
  cv::Mat1b ring = gt.clone();
  ring(cv::Rect(10, 10, 2, 2)).setTo(0);
  cv::Mat1f peak = cv::Mat1f::zeros(20, 20);
  peak(10, 10) = 1.f;
  CHECK_FALSE(localised_in_mask(peak, ring));
  CHECK(localised_in_box(peak, ring, 1));
}

TEST_CASE("summary: per-query means, per-class means and pooled per-class accuracy") {
  std::vector<QueryScore> scores(3);
  scores[0] = {"v0", "patient", {2, 8, 6, 4}, true, true};       // IoU 0.25, acc 2/6
  scores[1] = {"v1", "patient", {10, 10, 10, 10}, false, true};  // IoU 1, acc 10/10
  scores[2] = {"v0", "monitor", {0, 5, 5, 0}, false, false};     // IoU 0, acc 0
  const LangorSummary s = summarise_langor(scores);
  REQUIRE(s.classes.size() == 2);
  CHECK(s.classes[0].label == "patient");
  CHECK(s.classes[0].queries == 2);
  CHECK(s.classes[0].iou == Approx(62.5));
  CHECK(s.classes[0].loc_acc == Approx(50));
  CHECK(s.classes[0].acc == Approx(100.0 * 12 / 16));
  CHECK(s.queries == 3);
  CHECK(s.miou == Approx(100.0 * 1.25 / 3));
  CHECK(s.miou_class == Approx((62.5 + 0) / 2));
  CHECK(s.mlocacc == Approx(100.0 / 3));
  CHECK(s.mlocacc_box == Approx(200.0 / 3));
  CHECK(s.macc == Approx((75.0 + 0) / 2));
}
