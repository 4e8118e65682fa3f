// boxes.grabcut_priors (paper 002 Algorithm 1): the size ordering on a synthetic view with a known
// answer, mask priors refined by GrabCut, the detector threshold, and the kept prior.
#include "nodes/boxes/grabcut_priors.hpp"

#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "tests/boxes/grabcut_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using test::disc;
using test::iou;
using test::textured_background;

namespace {

DetectorPrior box_prior(int label, float score, float x1, float y1, float x2, float y2) {
  DetectorPrior p;
  p.label = label;
  p.score = score;
  p.confidence = score;
  p.box.x1 = x1;
  p.box.y1 = y1;
  p.box.x2 = x2;
  p.box.y2 = y2;
  return p;
}

}  // namespace

TEST_CASE("priors sorted by size: the object on a table is not swallowed by it", "[boxes]") {
  // A grey table (label 1) with a red instrument (label 2) on it; the detector lists the
  // instrument first. Painted as they are (no GrabCut) the answer is exact.
  cv::Mat3b image = textured_background(5);
  image(cv::Rect(20, 40, 80, 50)).setTo(cv::Vec3b(150, 150, 150));
  image.setTo(cv::Vec3b(220, 40, 30), disc(10));
  const std::vector<DetectorPrior> priors = {box_prior(2, 0.8f, 48, 38, 72, 62),
                                             box_prior(1, 0.9f, 20, 40, 100, 90)};
  GrabcutPriorOptions o;
  o.refine = false;
  PriorLabels sorted = refine_priors(image, {}, priors, o);
  CHECK(sorted.painted == 2);
  CHECK(cv::countNonZero(sorted.labels == 2) == 24 * 24);
  CHECK(cv::countNonZero(sorted.labels == 1) == 80 * 50 - 22 * 24);  // all but the overlap
  CHECK(sorted.confidence(50, 60) == 0.8f);
  CHECK(sorted.confidence(80, 30) == 0.9f);
  CHECK(cv::countNonZero(sorted.labels == -1) == 120 * 100 - 80 * 50 - 2 * 24);
  o.sort_by_size = false;  // detector order: the table, painted last, swallows the instrument
  const PriorLabels unsorted = refine_priors(image, {}, priors, o);
  CHECK(cv::countNonZero(unsorted.labels == 2) == 2 * 24);  // rows 38, 39 above the table
  CHECK(cv::countNonZero(unsorted.labels == 1) == 80 * 50);
  // Refined by GrabCut and sorted, the instrument keeps its pixels.
  o.sort_by_size = true;
  o.refine = true;
  sorted = refine_priors(image, {}, priors, o);
  CHECK(sorted.refined == 2);
  CHECK(cv::countNonZero((sorted.labels == 2) & disc(10)) > 0.9 * cv::countNonZero(disc(10)));
}

TEST_CASE("a coarse mask prior is refined by GrabCut from its border band", "[boxes]") {
  cv::Mat3b image = textured_background(6);
  image.setTo(cv::Vec3b(220, 40, 30), disc(22));
  GrabCutOptions o;
  // Masks 3 pixels too large and 2 too small: within the band t = 0.1 (w + h) / pi = 3 pixels
  // (GrabCut can only move the border inside the band: outside it is definite background).
  for (int radius : {25, 20}) {
    const cv::Mat1b coarse = disc(radius);
    const GrabCutMask g = grabcut_mask_prior(image, {}, coarse, 0.1f, o);
    CHECK(g.found);
    const double before = iou(coarse, disc(22)), after = iou(g.pixels, disc(22));
    INFO("radius " << radius << ": IoU " << before << " -> " << after);
    CHECK(after > 0.85);
    CHECK(after > before + 0.05);
  }
  // A mask that leaves GrabCut no background to learn from is kept as it is.
  const cv::Mat1b everything(100, 120, uchar(255));
  const GrabCutMask kept = grabcut_mask_prior(image, {}, everything, 0.1f, o);
  CHECK_FALSE(kept.found);
  CHECK(cv::countNonZero(kept.pixels) == 120 * 100);
}

TEST_CASE("detections below the threshold are not painted", "[boxes]") {
  const cv::Mat3b image = textured_background(7);
  GrabcutPriorOptions o;
  o.refine = false;
  const PriorLabels r = refine_priors(
      image, {}, {box_prior(1, 0.4f, 10, 10, 50, 50), box_prior(2, 0.5f, 60, 60, 70, 70)}, o);
  CHECK(r.painted == 1);
  CHECK(cv::countNonZero(r.labels == 1) == 0);
  CHECK(cv::countNonZero(r.labels == 2) == 100);
  DetectorPrior wrong = box_prior(1, 0.9f, 0, 0, 10, 10);
  wrong.mask = cv::Mat1b(10, 10, uchar(255));
  CHECK_THROWS_AS(refine_priors(image, {}, {wrong}, o), InputError);
}

TEST_CASE("detector prior maps: labels matched to classes, masks linked by box index", "[boxes]") {
  Capture capture;
  capture.name = "c";
  capture.classes = {{1, "operating table"}, {2, "patient"}};
  View view;
  view.name = "v";
  view.camera.width = 120;
  view.camera.height = 100;
  view.rgb = ImageSource::in_memory(textured_background(8));
  capture.views.push_back(view);
  view.name = "w";  // a view without detections: every pixel unlabelled
  capture.views.push_back(view);
  BoxSet boxes;
  ViewBoxes vb{"v", 4, {}};  // 4 VLM rounds
  vb.boxes.push_back(box_prior(0, 0.9f, 10, 10, 60, 60).box);
  vb.boxes.back().label = "Operating Table";
  vb.boxes.back().score = 0.9f;
  vb.boxes.back().support = 3;  // found in 3 of the 4 rounds
  vb.boxes.push_back(box_prior(0, 0.8f, 70, 10, 110, 50).box);
  vb.boxes.back().label = "patient";
  vb.boxes.back().score = 0.8f;
  vb.boxes.push_back(box_prior(0, 0.8f, 0, 70, 20, 90).box);
  vb.boxes.back().label = "lamp";  // no class of the capture
  boxes.views.push_back(vb);
  MaskSet masks;
  Mask m;
  m.pixels = cv::Mat1b::zeros(100, 120);
  m.pixels(cv::Rect(80, 20, 10, 10)).setTo(255);
  m.box_index = 1;  // the patient's box
  masks.views.push_back({"v", {m}});
  GrabcutPriorOptions o;
  o.refine = false;
  const DetectorPriorMaps r = detector_prior_maps(capture, boxes, masks, o);
  CHECK(r.unknown_labels == 1);
  CHECK(r.painted == 2);
  REQUIRE(r.priors.views.size() == 2);
  REQUIRE(r.priors.classes == std::vector<std::string>{"background", "operating table", "patient"});
  const SemanticView& v = r.priors.views[0];
  CHECK(cv::countNonZero(v.labels == 1) == 50 * 50);
  CHECK(cv::countNonZero(v.labels == 2) == 10 * 10);  // the mask, not the box
  CHECK(v.pixel(15 * 120 + 15, 3)[1] == Approx(0.9));
  CHECK(v.pixel(15 * 120 + 15, 3)[0] == Approx(0.05));
  CHECK(cv::countNonZero(r.priors.views[1].labels == -1) == 120 * 100);
  // Confidence: the score capped, or the cap times the fraction of rounds that found the box.
  o.max_confidence = 0.8f;
  CHECK(detector_prior_maps(capture, boxes, masks, o).priors.views[0].confidence(15, 15) ==
        Approx(0.8));
  o.confidence = PriorConfidence::Support;
  CHECK(detector_prior_maps(capture, boxes, masks, o).priors.views[0].confidence(15, 15) ==
        Approx(0.6));
  o.kind = PriorKind::Box;  // the patient's box instead of its mask
  CHECK(cv::countNonZero(detector_prior_maps(capture, boxes, masks, o).priors.views[0].labels ==
                         2) == 40 * 40);
  boxes.views[0].view = "elsewhere";
  CHECK_THROWS_AS(detector_prior_maps(capture, boxes, masks, o), InputError);
}
