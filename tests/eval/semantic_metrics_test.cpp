// eval.semantic's metrics (paper 002 §4.2) on a hand-computed confusion matrix.
#include "nodes/eval/semantic_metrics.hpp"

#include <catch2/catch.hpp>

#include "base/errors.hpp"
#include "nodes/eval/semantic_eval.hpp"
#include "nodes/scene/image_source.hpp"

using namespace gslift;

TEST_CASE("GA, CA and CP of a hand-computed confusion", "[eval]") {
  // ground truth   prediction      confusion (rows gt, cols pred 0 1 2 unlabelled)
  //   0 0 1          0 1 1           gt 0: 1 1 0 0
  //   1 2 2         -1 2 0           gt 1: 0 1 0 1
  //                                  gt 2: 1 0 1 0
  const cv::Mat1i gt = (cv::Mat1i(2, 3) << 0, 0, 1, 1, 2, 2);
  const cv::Mat1i pred = (cv::Mat1i(2, 3) << 0, 1, 1, -1, 2, 0);
  Confusion c(3);
  add_to_confusion(gt, pred, c);
  CHECK(c.at(0, 0) == 1);
  CHECK(c.at(0, 1) == 1);
  CHECK(c.at(1, 3) == 1);
  CHECK(c.at(2, 0) == 1);
  const SemanticScores s = semantic_scores(c);
  // tp = (1, 1, 1), fn = (1, 1, 1), fp = (1, 1, 0).
  CHECK(s.classes[0].fp == 1);
  CHECK(s.classes[1].fn == 1);
  CHECK(s.classes[2].fp == 0);
  CHECK(s.ga == Approx(50.0));
  CHECK(s.ca == Approx(50.0));
  CHECK(s.cp == Approx(100.0 * (0.5 + 0.5 + 1.0) / 3));
  CHECK(s.pixels == 6);
}

TEST_CASE("a class absent from the ground truth does not enter CA and CP", "[eval]") {
  // Classes 0..2, class 2 never in the ground truth but predicted once (a false positive of
  // class 2 that lowers class 0's recall).
  const cv::Mat1i gt = (cv::Mat1i(1, 4) << 0, 0, 1, 1);
  const cv::Mat1i pred = (cv::Mat1i(1, 4) << 0, 2, 1, 1);
  Confusion c(3);
  add_to_confusion(gt, pred, c);
  const SemanticScores s = semantic_scores(c);
  CHECK_FALSE(s.classes[2].present);
  CHECK(s.ga == Approx(75.0));
  CHECK(s.ca == Approx(75.0));   // (1/2 + 1) / 2
  CHECK(s.cp == Approx(100.0));  // (1 + 1) / 2
  // Pixels whose ground truth is no class are not evaluated; a prediction beyond the classes is
  // bad input.
  Confusion d(3);
  add_to_confusion((cv::Mat1i(1, 2) << -1, 7), (cv::Mat1i(1, 2) << 0, 0), d);
  CHECK(semantic_scores(d).pixels == 0);
  CHECK_THROWS_AS(add_to_confusion((cv::Mat1i(1, 1) << 0), (cv::Mat1i(1, 1) << 3), d), InputError);
}

TEST_CASE("confusion CSV and heat map", "[eval]") {
  Confusion c(2);
  c.at(0, 0) = 3;
  c.at(0, 1) = 1;
  c.at(1, 2) = 2;
  CHECK(confusion_csv(c, {"background", "table"}) ==
        "ground truth \\ predicted,background,table,unlabelled\nbackground,3,1,0\ntable,0,0,2\n");
  const cv::Mat png = confusion_heatmap(c, 4);
  CHECK(png.cols == 12);
  CHECK(png.rows == 8);
  CHECK(png.type() == CV_8UC3);
}

TEST_CASE("semantic evaluation pools training and held-out views apart", "[eval]") {
  Capture capture;
  capture.name = "c";
  for (int v = 0; v < 3; ++v) {
    View view;
    view.name = "v" + std::to_string(v);
    view.held_out = v == 2;
    // v1 has no ground truth: it is not evaluated.
    if (v != 1) view.gt_semantic = ImageSource::in_memory((cv::Mat1i(1, 2) << 0, 1));
    capture.views.push_back(view);
  }
  SemanticMaps predictions;
  predictions.classes = {"background", "table"};
  for (int v = 0; v < 3; ++v) {
    SemanticView sv;
    sv.view = "v" + std::to_string(v);
    sv.labels = v == 2 ? (cv::Mat1i(1, 2) << -1, 1) : (cv::Mat1i(1, 2) << 0, 0);
    predictions.views.push_back(sv);
  }
  const SemanticEvaluation e = evaluate_semantics(predictions, capture);
  REQUIRE(e.views.size() == 2);
  CHECK(semantic_scores(e.train).ga == Approx(50));
  CHECK(semantic_scores(e.test).ga == Approx(50));  // the unlabelled background pixel is a miss
  CHECK(semantic_scores(e.all).ga == Approx(50));
  SemanticEvalOptions o;
  o.unlabelled_as_background = true;
  CHECK(semantic_scores(evaluate_semantics(predictions, capture, o).test).ga == Approx(100));
  predictions.views[0].view = "elsewhere";
  CHECK_THROWS_AS(evaluate_semantics(predictions, capture), InputError);
}
