#include "nodes/ingest/capture_annotations.hpp"

#include <fstream>

#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/coco_rle.hpp"
#include "runtime/node.hpp"
#include "tests/ingest/small_capture.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// The small capture (8 x 6 views) with two VLM rounds on cam_00, box masks and automatic masks.
fs::path annotated_capture(const std::string& name, const std::string& manifest_extra) {
  const fs::path dir = test::write_small_capture(name, manifest_extra);
  write(dir / "vlm/cam_00/round_0.txt",
        "```json\n[{\"bbox_2d\": [2, 2, 6, 4], \"label\": \"table\"},"
        " {\"bbox_2d\": [3, 3, 3, 5], \"label\": \"flat\"},"
        " {\"bbox_2d\": [0, 0, 4, 6], \"label\": \"lamp\"}]\n```");
  write(dir / "vlm/cam_00/round_1.txt", "[{\"bbox_2d\": [0, 0, 8, 6], \"label\": \"room\"}]");
  // Round 0's masks: one per reply item; the mask of the degenerate item 1 has no box.
  cv::Mat1b left(6, 8, uchar(0));
  left(cv::Rect(0, 0, 4, 6)) = 255;
  const std::string rle_left = rle_counts_to_string(rle_encode(left));
  write(dir / "sam_box/cam_00/round_0.json",
        "[null, {\"size\": [6, 8], \"counts\": [48]}, {\"size\": [6, 8], \"counts\": \"" +
            rle_left + "\"}]");
  write(dir / "sam_auto/cam_01.json", "[{\"segmentation\": {\"size\": [6, 8], \"counts\": \"" +
                                          rle_left +
                                          "\"}, \"predicted_iou\": 0.8, \"granularity\": 2}]");
  return dir;
}

}  // namespace

TEST_CASE("VLM boxes of every view, in the capture's pixel grid") {
  const fs::path dir = annotated_capture("annotations_vlm", "vlm: {coords: pixels}\n");
  const Capture c = load_capture(dir);
  const BoxSet boxes = load_vlm_boxes(c);
  REQUIRE(boxes.views.size() == 3);
  const ViewBoxes& v0 = boxes.views[0];
  CHECK(v0.view == "cam_00");
  CHECK(v0.rounds == 2);
  REQUIRE(v0.boxes.size() == 3);
  CHECK(v0.boxes[0].label == "table");
  CHECK(v0.boxes[1].source_index == 2);
  CHECK(v0.boxes[2].round == 1);
  CHECK(v0.boxes[2].x2 == 8);
  CHECK(boxes.views[1].rounds == 0);
  CHECK(boxes.views[1].boxes.empty());

  SECTION("pixel coordinates follow the downscale") {
    const Capture half = load_capture(dir, {0, false, 2});
    const BoxSet b = load_vlm_boxes(half);
    CHECK(b.views[0].boxes[0].x1 == 1);
    CHECK(b.views[0].boxes[0].y2 == 2);
  }
  SECTION("norm1000 when asked explicitly") {
    const BoxSet b = load_vlm_boxes(c, {VlmCoords::Norm1000, 0});
    CHECK(b.views[0].boxes[2].x2 == Approx(8 * 8 / 1000.0));
  }
  SECTION("a requested round that is missing") {
    CHECK_THROWS_WITH(load_vlm_boxes(c, {VlmCoords::Auto, 3}), Contains("round_2.txt"));
  }
  SECTION("a malformed round beside a good one is skipped and counted") {
    write(dir / "vlm/cam_00/round_2.txt", "I see a table.");
    int unparsed = -1;
    const BoxSet b = load_vlm_boxes(c, {}, &unparsed);
    CHECK(unparsed == 1);
    CHECK(b.views[0].rounds == 3);
    CHECK(b.views[0].boxes.size() == 3);
  }
  SECTION("a view whose only reply is malformed") {
    write(dir / "vlm/cam_02/round_0.txt", "[{\"bbox_2d\": [1, 2]}]");
    CHECK_THROWS_WITH(load_vlm_boxes(c), Contains("cam_02/round_0.txt") && Contains("round 0") &&
                                             Contains("none of its 1 replies"));
  }
}

TEST_CASE("SAM box masks link to their boxes, automatic masks come per view") {
  const fs::path dir = annotated_capture("annotations_sam", "vlm: {coords: pixels}\n");
  const Capture c = load_capture(dir, {0, false, 2});
  const BoxSet boxes = load_vlm_boxes(c);
  const MaskSet masks = load_sam_box_masks(c, boxes);
  REQUIRE(masks.views.size() == 3);
  REQUIRE(masks.views[0].masks.size() == 1);  // item 0 is null, item 1's box was dropped
  const Mask& m = masks.views[0].masks[0];
  CHECK(m.box_index == 1);  // boxes[1] is reply item 2, "lamp"
  CHECK(m.label == "lamp");
  CHECK(m.pixels.size() == cv::Size(4, 3));  // brought to the half-resolution view
  CHECK(cv::countNonZero(m.pixels) == 6);

  const MaskSet autos = load_sam_auto_masks(c);
  REQUIRE(autos.views.size() == 3);
  CHECK(autos.views[0].masks.empty());
  REQUIRE(autos.views[1].masks.size() == 1);
  CHECK(autos.views[1].masks[0].granularity == 2);
  CHECK(autos.views[1].masks[0].score == 0.8f);

  write(dir / "sam_auto/cam_02.json", R"([{"segmentation": {"size": [5, 8], "counts": [40]}}])");
  CHECK_THROWS_WITH(load_sam_auto_masks(load_capture(dir)),
                    Contains("cam_02.json") && Contains("8 x 5"));
}
