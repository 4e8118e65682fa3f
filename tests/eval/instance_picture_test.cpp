// The ground truth | render | instances picture of instance-scored views, on maps whose colours
// follow from the matching by hand.
#include "nodes/eval/instance_picture.hpp"

#include "nodes/scene/caption_strip.hpp"
#include "nodes/scene/label_maps.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("instance picture: predictions take their matched ground truth's colour, others grey",
          "[eval]") {
  // Ground truth: instance 2 on the left half. Prediction: label 7 (matched to 2) on the left
  // half, label 9 (matched to nothing) in the bottom-right quadrant.
  cv::Mat1i truth(20, 20, 0), predicted(20, 20, 0);
  truth(cv::Rect(0, 0, 10, 20)) = 2;
  predicted(cv::Rect(0, 0, 10, 20)) = 7;
  predicted(cv::Rect(10, 10, 10, 10)) = 9;
  const cv::Mat3b render(20, 20, cv::Vec3b(50, 60, 70));
  const cv::Mat3b out = instance_comparison_picture(truth, render, predicted, {{7, 2}}, "cam_04");
  REQUIRE(!out.empty());
  const std::vector<LegendEntry> legend = {{"instance 2", label_colour(2)},
                                           {"unmatched prediction", cv::Vec3b(128, 128, 128)}};
  // Three 20-pixel panels side by side above the caption strip: the panels' bottom 20 rows.
  const int top = out.rows - caption_strip_height(out.cols, legend) - 20;
  REQUIRE(top > 0);
  const cv::Mat3b gt = out(cv::Rect(0, top, 20, 20));
  const cv::Mat3b instances = out(cv::Rect(out.cols - 20, top, 20, 20));
  CHECK(gt(5, 5) == label_colour(2));
  CHECK(gt(5, 15) == cv::Vec3b(0, 0, 0));
  CHECK(instances(5, 5) == label_colour(2));
  CHECK(instances(15, 15) == cv::Vec3b(128, 128, 128));
  CHECK(instances(5, 15) == cv::Vec3b(0, 0, 0));
  // The render panel sits between them, unchanged.
  CHECK(out(top + 10, out.cols / 2) == cv::Vec3b(50, 60, 70));

  CHECK(instance_comparison_picture(truth, cv::Mat3b(10, 10), predicted, {}, "x").empty());
}
