#include "nodes/ingest/sam_masks.hpp"

#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;

TEST_CASE("SAM automatic masks JSON: RLE in both forms, scores and granularity") {
  // 2 x 3 masks: "231" = counts 2 3 1 (see coco_rle_test), and [0, 6] = everything.
  const std::string text = R"([
    {"segmentation": {"size": [2, 3], "counts": "231"}, "bbox": [1, 0, 2, 2], "area": 3,
     "predicted_iou": 0.9, "stability_score": 0.95, "granularity": 1},
    {"segmentation": {"size": [2, 3], "counts": [0, 6]}, "bbox": [0, 0, 3, 2], "area": 6,
     "predicted_iou": 0.8, "stability_score": 0.9}])";
  const auto masks = parse_sam_auto_masks(text, "a.json");
  REQUIRE(masks.size() == 2);
  CHECK(masks[0].pixels(0, 1) == 255);
  CHECK(masks[0].pixels(1, 2) == 0);
  CHECK(cv::countNonZero(masks[0].pixels) == 3);
  CHECK(masks[0].score == 0.9f);
  CHECK(masks[0].granularity == 1);
  CHECK(cv::countNonZero(masks[1].pixels) == 6);
  CHECK(masks[1].granularity == 0);
}

TEST_CASE("SAM box masks JSON: aligned with boxes, null for no mask") {
  const auto masks = parse_sam_box_masks(
      R"([{"size": [2, 3], "counts": "231"}, null,
          {"segmentation": {"size": [2, 3], "counts": [5, 1]}, "score": 0.7}])",
      "b.json");
  REQUIRE(masks.size() == 3);
  REQUIRE(masks[0]);
  CHECK(masks[0]->box_index == 0);
  CHECK_FALSE(masks[1]);
  REQUIRE(masks[2]);
  CHECK(masks[2]->box_index == 2);
  CHECK(masks[2]->score == 0.7f);
  CHECK(masks[2]->pixels(1, 2) == 255);
}

TEST_CASE("broken SAM files give InputError naming the file") {
  CHECK_THROWS_WITH(parse_sam_auto_masks("{", "a.json"), Contains("a.json"));
  CHECK_THROWS_WITH(parse_sam_auto_masks("{}", "a.json"), Contains("a.json") && Contains("list"));
  CHECK_THROWS_WITH(parse_sam_auto_masks(R"([{"bbox": [0, 0, 1, 1]}])", "a.json"),
                    Contains("a.json mask 0"));
  CHECK_THROWS_WITH(
      parse_sam_auto_masks(R"([{"segmentation": {"size": [2, 3], "counts": [2, 3]}}])", "a.json"),
      Contains("a.json mask 0") && Contains("sum to 5"));
  CHECK_THROWS_WITH(parse_sam_box_masks(R"([null, 3])", "b.json"), Contains("b.json mask 1"));
}

TEST_CASE("instance maps become one mask per id") {
  cv::Mat1i ids(2, 3);
  ids << 0, 7, 7, 300, 0, 7;
  const auto masks = masks_from_instance_map(ids);
  REQUIRE(masks.size() == 2);
  CHECK(masks[0].label == "7");
  CHECK(cv::countNonZero(masks[0].pixels) == 3);
  CHECK(masks[1].label == "300");
  CHECK(masks[1].pixels(1, 0) == 255);
  CHECK(cv::countNonZero(masks[1].pixels) == 1);
}
