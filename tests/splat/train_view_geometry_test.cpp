// Held-out geometry metrics: coverage from ground-truth depth on a hand-built plane scene, and the
// depth / hole / floater fractions of a hand-placed model.
#include "nodes/splat/view_geometry.hpp"

#include "base/errors.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A view looking down +z from (cx, 0, 0) at the plane z = 2, with that plane as its ground truth.
View plane_view(const std::string& name, double centre_x) {
  View v;
  v.name = name;
  // 40 x 30, fx = fy = 20: at depth 2 it sees x in [-2, 2], y in [-1.5, 1.5].
  v.camera = test::centred_pinhole(40, 30, 20);
  v.pose.t = Eigen::Vector3d(-centre_x, 0, 0);  // x_cam = x_world - centre
  v.gt_depth = ImageSource::in_memory(cv::Mat1f(30, 40, 2.f));
  v.rgb = ImageSource::in_memory(cv::Mat3b(30, 40, cv::Vec3b(128, 128, 128)));
  return v;
}

}  // namespace

TEST_CASE("covered pixels: seen by a training view, inside it and not occluded there",
          "[splat][geometry]") {
  Capture capture;
  capture.views = {plane_view("test", 0), plane_view("train", 1)};
  capture.views[0].held_out = true;
  SECTION("a training camera 1 m to the right sees the test view's columns 10..39") {
    // Test pixel u has its centre at x = (u + 0.5 - 20) / 20 * 2; the training view sees x >= -1,
    // so u >= 10: 30 of 40 columns.
    const cv::Mat1b covered = covered_pixels(capture, 0, {1});
    CHECK(cv::countNonZero(covered) == 30 * 30);
    CHECK(covered(5, 9) == 0);
    CHECK(covered(5, 10) == 1);
  }
  SECTION("an occluder in front of the plane in the training view's top rows hides them") {
    cv::Mat1f occluded(30, 40, 2.f);
    occluded(cv::Rect(0, 0, 40, 10)) = 1.f;  // rows 0..9 see something at 1 m
    capture.views[1].gt_depth = ImageSource::in_memory(occluded);
    const cv::Mat1b covered = covered_pixels(capture, 0, {1});
    CHECK(cv::countNonZero(covered) == 30 * 20);
    CHECK(covered(9, 20) == 0);
    CHECK(covered(10, 20) == 1);
  }
  SECTION("a view without ground-truth depth is refused") {
    capture.views[1].gt_depth = ImageSource();
    CHECK_THROWS_AS(covered_pixels(capture, 0, {1}), InputError);
  }
}

TEST_CASE("view geometry: an empty model is all holes, a front plane is all floaters",
          "[splat][geometry]") {
  Capture capture;
  capture.views = {plane_view("test", 0), plane_view("train", 0)};
  capture.views[0].held_out = true;
  GaussianModel empty;
  const ViewGeometry none = view_geometry(empty, capture, 0, {1});
  CHECK(none.coverage == 1.0);
  CHECK(none.holes == 1.0);
  CHECK(none.holes_covered == 1.0);
  CHECK(none.depth_within_5pct == 0.0);
  CHECK(none.floaters == 0.0);
  CHECK(none.floaters_covered == 0.0);
  CHECK(std::isnan(none.depth_abs_rel_median));
  // The held-out image is scored over the background the model was trained on.
  capture.views[0].rgb = ImageSource::in_memory(cv::Mat3b(30, 40, cv::Vec3b(255, 255, 255)));
  CHECK(view_geometry(empty, capture, 0, {1}).psnr == Approx(0.0).margin(1e-9));
  CHECK(std::isinf(view_geometry(empty, capture, 0, {1}, Eigen::Vector3f::Ones()).psnr));

  // One large opaque flat Gaussian at z = 1.5 covering the view: every pixel is drawn 25% in
  // front of the true surface.
  GaussianModel front;
  front.resize(1);
  front.means = {0.f, 0.f, 1.5f};
  front.log_scales = {std::log(20.f), std::log(20.f), std::log(0.001f)};
  front.opacity_logits = {10.f};
  const ViewGeometry g = view_geometry(front, capture, 0, {1});
  CHECK(g.holes == 0.0);
  CHECK(g.floaters == 1.0);
  CHECK(g.floaters_covered == 1.0);
  CHECK(g.depth_within_5pct == 0.0);
  CHECK(g.depth_abs_rel_median == Approx(0.25).epsilon(1e-3));
}

TEST_CASE("median depth: the surface where the accumulated opacity reaches one half",
          "[splat][geometry]") {
  Capture capture;
  capture.views = {plane_view("test", 0), plane_view("train", 0)};
  capture.views[0].held_out = true;
  // Two view-filling flat Gaussians: a faint one at z = 1 (opacity 0.4) before the opaque true
  // surface at z = 2. Accumulated: 0.4 at the first, ~1 at the second: the median depth is 2 and
  // no pixel floats, while the expected depth (0.4 x 1 + 0.6 x 2) / 1 = 1.6 puts every pixel 20%
  // in front. With the front one at opacity 0.6 the front one is the surface: all floaters.
  auto layers = [](float front_opacity) {
    GaussianModel m;
    m.resize(2);
    m.means = {0.f, 0.f, 1.f, 0.f, 0.f, 2.f};
    for (int i = 0; i < 2; ++i) {
      m.log_scales[i * 3] = m.log_scales[i * 3 + 1] = std::log(50.f);
      m.log_scales[i * 3 + 2] = std::log(0.001f);
    }
    m.opacity_logits = {std::log(front_opacity / (1 - front_opacity)), 10.f};
    return m;
  };
  const GaussianModel faint = layers(0.4f);
  RenderSettings settings;
  settings.depth = true;
  settings.alpha = true;
  settings.normalize_depth = true;
  const View& v = capture.views[0];
  const RenderOutput out = render(faint, v.camera, v.pose, settings);
  const std::vector<float> median = median_depth(faint, v.pose, out);
  CHECK(median[15 * 40 + 20] == 2.f);
  // The rasterizer clamps a Gaussian's alpha at 0.99: (0.4 + 0.6 x 0.99 x 2) / (0.4 + 0.6 x 0.99).
  CHECK(out.depth[15 * 40 + 20] == Approx(1.588 / 0.994).epsilon(1e-3));
  const ViewGeometry g = view_geometry(faint, capture, 0, {1});
  CHECK(g.floaters == 0.0);
  CHECK(g.floaters_expected_depth == 1.0);
  CHECK(g.depth_abs_rel_median == Approx(0.0).margin(1e-6));
  const ViewGeometry front = view_geometry(layers(0.6f), capture, 0, {1});
  CHECK(front.floaters == 1.0);
  // A plane fills the view: no discontinuity, every floater is away from one.
  CHECK(front.floaters_at_discontinuity == 0.0);
  CHECK(front.floaters_away_from_discontinuity == 1.0);
  CHECK(front.depth_abs_rel_median == Approx(0.5).epsilon(1e-4));
}

TEST_CASE("depth discontinuities: pixels within the radius of a depth jump or a missing depth",
          "[splat][geometry]") {
  // 12 x 8: depth 2 left of column 6, 2.1 (5% deeper: no jump at 10%) from 6, and a step to 3
  // (50% deeper than 2.1) from column 10. One pixel without depth at (row 7, column 0).
  cv::Mat1f depth(8, 12, 2.f);
  depth.colRange(6, 12).setTo(2.1f);
  depth.colRange(10, 12).setTo(3.f);
  depth(7, 0) = 0.f;
  const cv::Mat1b near = depth_discontinuities(depth, 0.1, 2);
  // The 9 | 10 edge marks columns 9 and 10; radius 2 reaches columns 7-11 on every row.
  for (int y = 0; y < 8; ++y) {
    for (int x = 7; x < 12; ++x) CHECK(near(y, x) == 1);
    CHECK(near(y, 6) == 0);
  }
  // The missing pixel (7,0) and its neighbours (6,0) and (7,1) are edge pixels: rows 4-7 x
  // columns 0-2 around (6,0), rows 5-7 x columns 0-3 around (7,1): 12 + 3 pixels.
  CHECK(near(4, 0) == 1);
  CHECK(near(4, 3) == 0);
  CHECK(near(5, 3) == 1);
  CHECK(near(3, 0) == 0);
  CHECK(near(7, 4) == 0);
  CHECK(cv::countNonZero(near) == 8 * 5 + 15);
  // Radius 0: only the edge pixels themselves (columns 9, 10 and the three around the hole).
  CHECK(cv::countNonZero(depth_discontinuities(depth, 0.1, 0)) == 8 * 2 + 3);
}

TEST_CASE("view geometry picture: floaters red, holes blue, uncovered surfaces grey",
          "[splat][geometry]") {
  // The training camera 1 m to the right covers the test view's columns 10..39 (first case).
  Capture capture;
  capture.views = {plane_view("test", 0), plane_view("train", 1)};
  capture.views[0].held_out = true;
  cv::Mat3b picture;
  view_geometry(GaussianModel{}, capture, 0, {1}, Eigen::Vector3f::Zero(), &picture);
  REQUIRE(picture.size() == cv::Size(40, 30));
  CHECK(picture(5, 20) == cv::Vec3b(0, 64, 255));  // covered and empty: a hole
  CHECK(picture(5, 5) == cv::Vec3b(85, 85, 85));   // uncovered: black render greyed
  GaussianModel front;  // the opaque plane at z = 1.5 of the first case: all floaters
  front.resize(1);
  front.means = {0.f, 0.f, 1.5f};
  front.log_scales = {std::log(20.f), std::log(20.f), std::log(0.001f)};
  front.opacity_logits = {10.f};
  view_geometry(front, capture, 0, {1}, Eigen::Vector3f::Zero(), &picture);
  CHECK(picture(5, 20) == cv::Vec3b(255, 0, 0));
}
