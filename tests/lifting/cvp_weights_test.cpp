#include "nodes/lifting/cvp_weights.hpp"

#include <cmath>

#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("CVP weights (LangOR Eq. 4) on a hand-computed plus-shaped mask") {
  // Centre (2,2) and its 4 neighbours: centroid (2,2); squared distances 0,1,1,1,1, mean 0.8 =
  // RMS radius^2. Neighbour weight = exp(-(1/0.8) / (2 * 0.25)) / 5 = exp(-2.5) / 5.
  cv::Mat1b mask = cv::Mat1b::zeros(5, 5);
  mask(2, 2) = mask(1, 2) = mask(3, 2) = mask(2, 1) = mask(2, 3) = 255;
  const MaskPixelWeights w = cvp_weights(mask, 0.5);
  REQUIRE(w.pixels.size() == 5);
  for (size_t i = 0; i < w.pixels.size(); ++i) {
    const bool centre = w.pixels[i] == cv::Point(2, 2);
    CHECK(w.weights[i] == Approx(centre ? 0.2 : std::exp(-2.5) / 5).epsilon(1e-12));
  }
}

TEST_CASE("CVP weights use RMS-radius units and equalise mask totals") {
  // 4x4 square: offsets from the centroid are +-0.5, +-1.5 per axis, mean squared radius
  // 2 * 1.25 = 2.5; the corner (1.5, 1.5) has r^2 = 4.5 / 2.5 = 1.8 RMS radii squared, so its
  // weight is exp(-1.8 / (2 * 0.5^2)) / 16.
  cv::Mat1b small = cv::Mat1b::zeros(20, 20), big = cv::Mat1b::zeros(40, 40);
  small(cv::Rect(2, 2, 4, 4)).setTo(255);
  big(cv::Rect(2, 2, 12, 12)).setTo(255);
  const auto ws = cvp_weights(small, 0.5), wb = cvp_weights(big, 0.5);
  REQUIRE(ws.pixels.front() == cv::Point(2, 2));
  CHECK(ws.weights.front() == Approx(std::exp(-3.6) / 16).epsilon(1e-12));
  // Total weight is the mean of exp(-r^2 / 2 sigma^2) in RMS units: about the same for a mask of
  // 16 and one of 144 pixels, so both get a similar share of the jointly drawn samples.
  double sum_s = 0, sum_b = 0;
  for (double v : ws.weights) sum_s += v;
  for (double v : wb.weights) sum_b += v;
  CHECK(sum_s == Approx(sum_b).epsilon(0.1));
}

TEST_CASE("CVP weights edge cases") {
  CHECK(cvp_weights(cv::Mat1b::zeros(3, 3), 0.5).pixels.empty());
  cv::Mat1b one = cv::Mat1b::zeros(3, 3);
  one(1, 1) = 1;
  CHECK(cvp_weights(one, 0.5).weights == std::vector<double>{1.0});
  CHECK_THROWS_AS(cvp_weights(one, 0.0), std::invalid_argument);
}
