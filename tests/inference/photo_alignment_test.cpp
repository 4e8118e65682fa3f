// Masks registered to a view's photo (photo_alignment.hpp): a known shift between a render and
// its photo is recovered and moves the masks, no shift where the images agree.
#include "nodes/inference/photo_alignment.hpp"

#include <opencv2/imgproc.hpp>

#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A smooth random texture (ECC needs gradients everywhere), fixed seed.
cv::Mat1f texture(cv::Size size) {
  cv::Mat1f t(size);
  cv::RNG rng(7);
  rng.fill(t, cv::RNG::UNIFORM, 0.f, 1.f);
  cv::GaussianBlur(t, t, cv::Size(0, 0), 3.0);
  return t;
}

// `image` with its content moved by (dx, dy) whole pixels (edges replicated).
cv::Mat1f moved(const cv::Mat1f& image, int dx, int dy) {
  cv::Mat1f out;
  cv::warpAffine(image, out, cv::Matx23f(1, 0, float(dx), 0, 1, float(dy)), image.size(),
                 cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  return out;
}

}  // namespace

TEST_CASE("photo alignment: a render 3 px left and 2 px below its photo is moved onto it",
          "[inference][photo_alignment]") {
  const cv::Mat1f render = texture({160, 120});
  const cv::Mat1f photo = moved(render, 3, -2);  // the photo's content sits at render + (3, -2)
  const PhotoAlignment a = align_render_to_photo(render, photo, 0.003);
  CHECK(a.shift_x == Approx(3.0).margin(0.05));
  CHECK(a.shift_y == Approx(-2.0).margin(0.05));
  CHECK(a.correlation_after > a.correlation_before + 0.003);
  CHECK(a.correlation_after > 0.99);
  REQUIRE(a.applied);
  // A mask rendered at the view's pose follows the content.
  cv::Mat1b mask = cv::Mat1b::zeros(render.size());
  mask(cv::Rect(40, 30, 20, 10)) = 255;
  const cv::Mat1b aligned = align_image(mask, a);
  cv::Mat1b expected = cv::Mat1b::zeros(render.size());
  expected(cv::Rect(43, 28, 20, 10)) = 255;
  CHECK(cv::countNonZero(aligned != expected) == 0);
  // A label map (32-bit ids) moves the same way, its ids kept: nearest pixel, no blending.
  cv::Mat1i labels = cv::Mat1i::zeros(render.size());
  labels(cv::Rect(40, 30, 20, 10)) = 70000;
  cv::Mat1i expected_labels = cv::Mat1i::zeros(render.size());
  expected_labels(cv::Rect(43, 28, 20, 10)) = 70000;
  const cv::Mat1i moved_labels = align_image(labels, a);
  CHECK(cv::countNonZero(moved_labels != expected_labels) == 0);
  // The same shift below the gain asked for is recorded, not applied: the mask stays.
  const PhotoAlignment strict = align_render_to_photo(render, photo, 0.9);
  CHECK_FALSE(strict.applied);
  CHECK(strict.shift_x == Approx(3.0).margin(0.05));
  CHECK(cv::countNonZero(cv::Mat1b(align_image(mask, strict)) != mask) == 0);
}

TEST_CASE("photo alignment: images that agree get no shift, and sizes must match",
          "[inference][photo_alignment]") {
  const cv::Mat1f render = texture({160, 120});
  const PhotoAlignment a = align_render_to_photo(render, render.clone(), 0.003);
  CHECK(a.correlation_before == Approx(1.0).margin(1e-6));
  CHECK_FALSE(a.applied);
  CHECK(std::abs(a.shift_x) < 0.01);
  CHECK(std::abs(a.shift_y) < 0.01);
  CHECK_THROWS_AS(align_render_to_photo(render, texture({80, 60}), 0.003), std::invalid_argument);
}
