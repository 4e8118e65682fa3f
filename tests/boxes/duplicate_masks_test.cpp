// boxes.to_masks duplicates: a patient on an operating table, where the table's box-prompted mask
// is the patient (the box-prompted segmenter returned the most salient object in the table's
// box), as on the embedded OR (docs/langor.md "Where the classes are lost" 2).
#include "nodes/boxes/duplicate_masks.hpp"

#include <opencv2/imgproc.hpp>

#include "nodes/boxes/box_masks.hpp"
#include "tests/boxes/grabcut_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using test::disc;
using test::iou;
using test::textured_background;

namespace {

Box make_box(float x1, float y1, float x2, float y2, const std::string& label) {
  Box b;
  b.x1 = x1;
  b.y1 = y1;
  b.x2 = x2;
  b.y2 = y2;
  b.label = label;
  return b;
}

// The patient: disc() (radius 22 at (60, 50), bounding rectangle x 38..82, y 28..72), red.
// The table: the rectangle x 15..104, y 35..79 under it, brown, at 2 m against a 3 m floor; the
// patient lies on it at 1.7 m.
struct TableScene {
  cv::Mat3b rgb = textured_background(4);
  cv::Mat1f depth = cv::Mat1f(100, 120, 3.f);
  cv::Mat1b table = cv::Mat1b::zeros(100, 120);  // the table's visible pixels
  std::vector<Box> boxes = {make_box(33, 23, 87, 77, "patient"),
                            make_box(15, 35, 105, 80, "operating table")};
  TableScene() {
    table(cv::Rect(15, 35, 90, 45)).setTo(255);
    table.setTo(0, disc());
    rgb.setTo(cv::Vec3b(60, 110, 160), table);
    depth.setTo(2.f, table);
    rgb.setTo(cv::Vec3b(30, 40, 220), disc());
    depth.setTo(1.7f, disc());
  }
  // What the segmenter gave: the patient for both boxes.
  std::vector<Mask> masks() const {
    std::vector<Mask> m(2);
    for (int i = 0; i < 2; ++i) {
      m[i].pixels = disc().clone();
      m[i].label = boxes[i].label;
      m[i].box_index = i;
    }
    return m;
  }
};

}  // namespace

TEST_CASE("box_fit: IoU of the box with the mask's bounding rectangle", "[boxes]") {
  const TableScene s;
  // Bounding rectangle of the disc: 45 x 45 = 2025 pixels, inside the 54 x 54 patient box.
  CHECK(box_fit(s.boxes[0], disc()) == Approx(2025.0 / 2916.0));
  // The table box (90 x 45) holds rows 35..72 of it: 45 x 38 = 1710 of 4050 + 2025 - 1710.
  CHECK(box_fit(s.boxes[1], disc()) == Approx(1710.0 / 4365.0));
  CHECK(box_fit(s.boxes[0], cv::Mat1b::zeros(100, 120)) == 0.0);
}

TEST_CASE("find_duplicate_masks: the box that fits the shared mask worse is the duplicate",
          "[boxes]") {
  const TableScene s;
  std::vector<cv::Mat1b> masks = {disc(), disc()};
  CHECK(find_duplicate_masks(s.boxes, masks, 0.8f) == std::vector<int>{-1, 0});
  // Listed the other way round, the table is still the duplicate.
  CHECK(find_duplicate_masks({s.boxes[1], s.boxes[0]}, masks, 0.8f) == std::vector<int>{1, -1});
  // A smaller disc (radius 18) for the table: mask IoU (18/22)^2 about 0.67, under 0.8.
  masks[1] = disc(18);
  CHECK(find_duplicate_masks(s.boxes, masks, 0.8f) == std::vector<int>{-1, -1});
  CHECK(find_duplicate_masks(s.boxes, masks, 0.6f) == std::vector<int>{-1, 0});
  // One label: two boxes of one object are not a duplicate.
  masks[1] = disc();
  std::vector<Box> same = s.boxes;
  same[1].label = "patient";
  CHECK(find_duplicate_masks(same, masks, 0.8f) == std::vector<int>{-1, -1});
  // The table's box fits the patient's mask 0.392 / 0.694 = 0.56 times as well as the
  // patient's box: a duplicate at fit ratio 0.85 and 0.6, not at 0.5.
  CHECK(find_duplicate_masks(s.boxes, masks, 0.8f, 0.85f) == std::vector<int>{-1, 0});
  CHECK(find_duplicate_masks(s.boxes, masks, 0.8f, 0.6f) == std::vector<int>{-1, 0});
  CHECK(find_duplicate_masks(s.boxes, masks, 0.8f, 0.5f) == std::vector<int>{-1, -1});
  // A second box about the patient, 3 pixels tighter on each side (fit 2025 / 2500 = 0.81), is
  // the patient named twice: the patient's box fits 0.694 / 0.81 = 0.86 times as well, not a
  // duplicate at 0.85, a duplicate of the tighter box at 1.
  const std::vector<Box> twice = {s.boxes[0], make_box(35, 25, 85, 75, "nurse")};
  CHECK(box_fit(twice[1], disc()) == Approx(2025.0 / 2500.0));
  CHECK(find_duplicate_masks(twice, masks, 0.8f, 0.85f) == std::vector<int>{-1, -1});
  CHECK(find_duplicate_masks(twice, masks, 0.8f, 1.f) == std::vector<int>{1, -1});
  // Equal fits keep both.
  CHECK(find_duplicate_masks({s.boxes[0], make_box(33, 23, 87, 77, "x")}, masks, 0.8f) ==
        std::vector<int>{-1, -1});
}

TEST_CASE("repair_duplicate_masks: keep, drop and regrow the table's mask", "[boxes]") {
  const TableScene s;
  GrabCutOptions grabcut;
  DuplicateMaskOptions o;

  std::vector<Mask> masks = s.masks();
  DuplicateRepairCount c = repair_duplicate_masks(s.rgb, s.depth, s.boxes, masks, o, grabcut);
  CHECK(c.duplicates == 0);  // keep (LangOR) does not look
  REQUIRE(masks.size() == 2);
  CHECK(cv::countNonZero(masks[1].pixels != disc()) == 0);

  o.repair = DuplicateRepair::Drop;
  c = repair_duplicate_masks(s.rgb, s.depth, s.boxes, masks, o, grabcut);
  CHECK(c.duplicates == 1);
  CHECK(c.dropped == 1);
  REQUIRE(masks.size() == 1);
  CHECK(masks[0].label == "patient");

  o.repair = DuplicateRepair::Regrow;
  masks = s.masks();
  c = repair_duplicate_masks(s.rgb, s.depth, s.boxes, masks, o, grabcut);
  CHECK(c.duplicates == 1);
  CHECK(c.regrown == 1);
  CHECK(c.dropped == 0);
  REQUIRE(masks.size() == 2);
  CHECK(cv::countNonZero(masks[0].pixels != disc()) == 0);  // the owner keeps its mask
  const Mask& table = masks[1];
  CHECK(table.label == "operating table");
  CHECK(table.box_index == 1);
  // The regrown mask is the table around the patient and none of the patient: measured IoU 1
  // with the table's 90 x 45 - 1378 = 2672 visible pixels (the patient's are definite background,
  // the table's colour and depth differ from the floor's).
  CHECK(cv::countNonZero(table.pixels & disc()) == 0);
  CHECK(cv::countNonZero(s.table) == 2672);
  CHECK(iou(table.pixels, s.table) > 0.99);

  o.min_pixels = 100000;  // more than the image: the regrown mask is dropped
  masks = s.masks();
  c = repair_duplicate_masks(s.rgb, s.depth, s.boxes, masks, o, grabcut);
  CHECK(c.regrown == 0);
  CHECK(c.dropped == 1);
  CHECK(masks.size() == 1);
}
