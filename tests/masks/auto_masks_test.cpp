// Classical automatic masks on a drawn image whose objects are known, and their SAM-form JSON.
#include "nodes/masks/auto_masks.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "nodes/ingest/sam_masks.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A grey 160x120 background with a red box (its left half dark red, its right half light red:
// two parts of one object) and a blue disc.
cv::Mat drawn_scene(cv::Mat1b& box, cv::Mat1b& disc) {
  cv::Mat rgb(120, 160, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::rectangle(rgb, cv::Rect(10, 20, 30, 60), cv::Scalar(150, 20, 20), -1);
  cv::rectangle(rgb, cv::Rect(40, 20, 30, 60), cv::Scalar(220, 40, 40), -1);
  cv::circle(rgb, {115, 60}, 25, cv::Scalar(20, 20, 200), -1);
  box = cv::Mat1b::zeros(120, 160);
  box(cv::Rect(10, 20, 60, 60)).setTo(255);
  disc = cv::Mat1b::zeros(120, 160);
  cv::circle(disc, {115, 60}, 25, cv::Scalar(255), -1);
  return rgb;
}

double best_iou(const std::vector<Mask>& masks, const cv::Mat1b& target, int granularity) {
  double best = 0;
  for (const Mask& m : masks)
    if (m.granularity == granularity) best = std::max(best, mask_iou(m.pixels, target));
  return best;
}

}  // namespace

TEST_CASE("graph segmentation at two scales: whole objects coarse, parts fine") {
  cv::Mat1b box, disc;
  const cv::Mat rgb = drawn_scene(box, disc);
  AutoMaskOptions o;
  // Scales for this 160-px image: the options scale k with the width (k * 160 / 640 = 30000 and
  // 1000). Segments under min_area merge into a neighbour: the one-pixel rings that the smoothing
  // leaves along each edge (sigma 0.8) are absorbed.
  o.scales = {120000, 4000};
  o.keep.min_area = 400;
  const std::vector<Mask> masks = auto_masks(rgb, o);
  // Fine: the disc, and each half of the box on its own (IoU > 0.9: the one-pixel ring that the
  // smoothing blurs along each edge goes to one side or the other).
  cv::Mat1b left = cv::Mat1b::zeros(120, 160), right = cv::Mat1b::zeros(120, 160);
  left(cv::Rect(10, 20, 30, 60)).setTo(255);
  right(cv::Rect(40, 20, 30, 60)).setTo(255);
  CHECK(best_iou(masks, disc, 1) > 0.9);
  CHECK(best_iou(masks, left, 1) > 0.9);
  CHECK(best_iou(masks, right, 1) > 0.9);
  // Coarse: the two halves (a weak edge) merge into the box.
  CHECK(best_iou(masks, box, 0) > 0.9);
  // Deterministic, and every mask is at least min_area and below 90% of the view.
  const std::vector<Mask> again = auto_masks(rgb, o);
  REQUIRE(again.size() == masks.size());
  for (size_t k = 0; k < masks.size(); ++k) {
    CHECK(cv::countNonZero(masks[k].pixels != again[k].pixels) == 0);
    CHECK(cv::countNonZero(masks[k].pixels) >= 400);
    CHECK(cv::countNonZero(masks[k].pixels) <= 0.9 * 120 * 160);
  }
}

TEST_CASE("automatic masks round-trip through the SAM automatic-mask JSON") {
  cv::Mat1b box, disc;
  const cv::Mat rgb = drawn_scene(box, disc);
  AutoMaskOptions o;
  o.scales = {120000, 4000};
  o.keep.min_area = 400;
  const std::vector<Mask> masks = auto_masks(rgb, o);
  nlohmann::json list = nlohmann::json::array();
  for (const Mask& m : masks) {
    nlohmann::json rec = sam_mask_record(m.pixels, 1.0, 1.0);
    rec["granularity"] = m.granularity;
    list.push_back(rec);
  }
  const std::vector<Mask> back = parse_sam_auto_masks(list.dump(), "test");
  REQUIRE(back.size() == masks.size());
  for (size_t k = 0; k < masks.size(); ++k) {
    CHECK(cv::countNonZero(back[k].pixels != masks[k].pixels) == 0);
    CHECK(back[k].granularity == masks[k].granularity);
  }
}

TEST_CASE("masks.folder reads the alpha of RGBA renders, and refuses a file without alpha") {
  const auto dir = test::scratch_dir("mask_folder_alpha");
  // An 8x4 white RGBA render whose left half is opaque but for one pixel at alpha 0.2: its grey
  // level is white everywhere, so only the alpha says where the object is.
  cv::Mat bgra(4, 8, CV_8UC4, cv::Scalar(255, 255, 255, 0));
  bgra(cv::Rect(0, 0, 4, 4)).setTo(cv::Scalar(255, 255, 255, 255));
  bgra.at<cv::Vec4b>(0, 0)[3] = 51;
  cv::imwrite((dir / "r_0.png").string(), bgra);
  Capture capture;
  capture.name = "lego";
  View view;
  view.name = "r_0";
  view.camera.width = 4;  // half the file's size: the mask is resized with the area filter
  view.camera.height = 2;
  capture.views.push_back(view);

  const MaskSet alpha = mask_folder(capture, dir, ViewSet::All, "lego", MaskChannel::Alpha);
  REQUIRE(alpha.views.size() == 1);
  const cv::Mat1b m = alpha.views[0].masks.at(0).pixels;
  REQUIRE(m.size() == cv::Size(4, 2));
  // Each output pixel averages a 2x2 block: (51 + 3 x 255) / 4 = 204 at (0, 0), still inside;
  // the right half is clear.
  for (int y = 0; y < 2; ++y) {
    CHECK(m(y, 0) != 0);
    CHECK(m(y, 1) != 0);
    CHECK(m(y, 2) == 0);
    CHECK(m(y, 3) == 0);
  }
  CHECK(alpha.views[0].masks[0].label == "lego");
  const MaskSet grey = mask_folder(capture, dir, ViewSet::All, "lego");
  CHECK(cv::countNonZero(grey.views.at(0).masks.at(0).pixels) == 8);

  cv::imwrite((dir / "r_0.png").string(), cv::Mat(4, 8, CV_8UC3, cv::Scalar(255, 255, 255)));
  CHECK_THROWS_WITH(mask_folder(capture, dir, ViewSet::All, "lego", MaskChannel::Alpha),
                    Catch::Matchers::Contains("r_0.png has no alpha channel"));
}
