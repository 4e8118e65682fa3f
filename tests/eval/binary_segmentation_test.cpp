// NVOS / SPIn-NeRF binary segmentation scores on hand-computed masks.
#include "nodes/eval/binary_segmentation.hpp"

#include "base/errors.hpp"
#include "tests/eval/mask_blocks.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::block;

namespace {
Mask labelled(cv::Mat1b pixels, const std::string& label) {
  Mask m;
  m.pixels = pixels;
  m.label = label;
  return m;
}
}  // namespace

TEST_CASE("binary IoU and accuracy of a hand-counted mask pair") {
  // 4x4 image: prediction = columns 0-1 of rows 0-1 (4 px), truth = columns 1-3 of rows 0-1
  // (6 px). TP = 2, FP = 2, FN = 4, TN = 16 - 8 = 8.
  const BinaryCounts c = binary_counts(block(4, 4, {0, 0, 2, 2}), block(4, 4, {1, 0, 3, 2}));
  CHECK(c.tp == 2);
  CHECK(c.fp == 2);
  CHECK(c.fn == 4);
  CHECK(c.tn == 8);
  CHECK(binary_iou(c) == Approx(2.0 / 8.0));
  CHECK(binary_accuracy(c) == Approx(10.0 / 16.0));
  CHECK(binary_precision(c) == Approx(2.0 / 4.0));
  CHECK(binary_recall(c) == Approx(2.0 / 6.0));
  // Nothing selected: no wrong pixel (precision 1), the whole object missed (recall 0).
  const BinaryCounts none = binary_counts(cv::Mat1b::zeros(4, 4), block(4, 4, {1, 0, 3, 2}));
  CHECK(binary_precision(none) == 1.0);
  CHECK(binary_recall(none) == 0.0);
  CHECK(binary_iou(binary_counts(cv::Mat1b::zeros(2, 2), cv::Mat1b::zeros(2, 2))) == 1.0);
  CHECK_THROWS_AS(binary_counts(cv::Mat1b::zeros(2, 2), cv::Mat1b::zeros(3, 2)), InputError);
}

TEST_CASE("scores average over target views per prompt, then over prompts") {
  MaskSet pred, truth;
  // Prompt "a": perfect in v1, IoU 0.25 / accuracy 10/16 in v2. Prompt "b": perfect in v1 and
  // absent from v2's truth: v2 does not show it and is no target view for it.
  pred.views = {
      {"v1", {labelled(block(4, 4, {0, 0, 2, 2}), "a"), labelled(block(4, 4, {3, 3, 1, 1}), "b")}},
      {"v2", {labelled(block(4, 4, {0, 0, 2, 2}), "a"), labelled(block(4, 4, {0, 3, 2, 1}), "b")}},
      {"v3", {labelled(block(4, 4, {0, 0, 4, 4}), "a")}}};  // no truth: not a target
  truth.views = {
      {"v1", {labelled(block(4, 4, {0, 0, 2, 2}), "a"), labelled(block(4, 4, {3, 3, 1, 1}), "b")}},
      {"v2", {labelled(block(4, 4, {1, 0, 3, 2}), "a")}}};
  BinarySegmentationSummary s = score_binary_segmentation(pred, truth, {});
  REQUIRE(s.labels.size() == 2);
  CHECK(s.views.size() == 3);
  CHECK(s.labels[0].label == "a");
  CHECK(s.labels[0].views == 2);
  CHECK(s.labels[0].iou == Approx(100 * (1.0 + 0.25) / 2));
  CHECK(s.labels[0].accuracy == Approx(100 * (1.0 + 10.0 / 16) / 2));
  CHECK(s.labels[1].views == 1);
  CHECK(s.labels[1].iou == Approx(100.0));
  CHECK(s.labels[1].accuracy == Approx(100.0));
  CHECK(s.miou == Approx((62.5 + 100.0) / 2));
  // Precision of "a": 1 in v1, 2 / 4 in v2; recall 1 and 2 / 6.
  CHECK(s.labels[0].precision == Approx(100 * (1.0 + 0.5) / 2));
  CHECK(s.labels[0].recall == Approx(100 * (1.0 + 2.0 / 6) / 2));
  CHECK(s.mprecision == Approx((75.0 + 100.0) / 2));
  CHECK(s.mrecall == Approx((100 * (1.0 + 2.0 / 6) / 2 + 100.0) / 2));
  // Excluding v1 (say, the prompt's view) leaves v2 alone.
  s = score_binary_segmentation(pred, truth, {{"v1"}});
  REQUIRE(s.views.size() == 1);
  CHECK(s.labels.size() == 1);
  CHECK(s.labels[0].iou == Approx(25.0));
  // A prediction whose label no truth view has is an error, not a silent zero.
  pred.views[0].masks[0].label = "c";
  CHECK_THROWS_AS(score_binary_segmentation(pred, truth, {}), InputError);
}
