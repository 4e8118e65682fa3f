// Random initialisation for captures with neither sparse points nor a depth prior.
#include "base/errors.hpp"
#include "nodes/splat/initialise.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A 40 x 30 view looking down +z from (x, 0, 0), its image a single colour.
View side_view(const std::string& name, double x, cv::Vec3b colour) {
  View v;
  v.name = name;
  v.camera = test::centred_pinhole(40, 30, 20);
  v.pose.t = Eigen::Vector3d(-x, 0, 0);
  v.rgb = ImageSource::in_memory(cv::Mat3b(30, 40, colour));
  return v;
}

bool inside(const View& v, const Eigen::Vector3d& world) {
  const Eigen::Vector3d p = v.pose.to_camera(world);
  if (p.z() <= 0) return false;
  const double u = v.camera.fx * p.x() / p.z() + v.camera.cx;
  const double w = v.camera.fy * p.y() / p.z() + v.camera.cy;
  return u >= 0 && w >= 0 && u < v.camera.width && w < v.camera.height;
}

}  // namespace

TEST_CASE("random init: points in the volume two training views share, coloured by their ray",
          "[splat][init]") {
  Capture capture;
  capture.name = "rig";
  capture.views = {side_view("a", 0, {255, 0, 0}), side_view("b", 1, {0, 0, 255})};
  const ColouredPoints pts = random_volume_points(capture, {0, 1}, 500, 0.5, 4.0, 0.0, 7);
  REQUIRE(pts.xyz.size() == 500u);
  for (size_t i = 0; i < pts.xyz.size(); ++i) {
    const Eigen::Vector3d& x = pts.xyz[i];
    // Both views look down +z from z = 0: depth is z in either camera.
    CHECK(x.z() >= 0.5 - 1e-9);
    CHECK(x.z() <= 4.0 + 1e-9);
    CHECK(inside(capture.views[0], x));
    CHECK(inside(capture.views[1], x));
    // The colour is the sampling view's: pure red or pure blue.
    CHECK((pts.rgb[i] == Eigen::Vector3d(1, 0, 0) || pts.rgb[i] == Eigen::Vector3d(0, 0, 1)));
  }
  // Deterministic for a seed, different for another.
  const ColouredPoints again = random_volume_points(capture, {0, 1}, 500, 0.5, 4.0, 0.0, 7);
  CHECK(again.xyz == pts.xyz);
  const ColouredPoints other = random_volume_points(capture, {0, 1}, 500, 0.5, 4.0, 0.0, 8);
  CHECK(other.xyz != pts.xyz);
}

TEST_CASE("random init: views that share no volume are refused, naming the capture",
          "[splat][init]") {
  Capture capture;
  capture.name = "apart";
  // 100 m apart, seeing at most 4 m: nothing in common.
  capture.views = {side_view("a", 0, {9, 9, 9}), side_view("b", 100, {9, 9, 9})};
  CHECK_THROWS_WITH(random_volume_points(capture, {0, 1}, 50, 0.5, 4.0, 0.0, 1),
                    Catch::Contains("'apart'") && Catch::Contains("common volume"));
}

TEST_CASE("auto init falls back to random points when there are neither points nor depth",
          "[splat][init]") {
  Capture capture;
  capture.name = "rig";
  capture.views = {side_view("a", 0, {200, 100, 50}), side_view("b", 1, {200, 100, 50})};
  InitialiseOptions o;
  o.random_points = 300;
  const GaussianModel model = initialise_gaussians(capture, o);
  CHECK(model.size() == 300u);
  o.source = InitSource::Points;
  CHECK_THROWS_AS(initialise_gaussians(capture, o), InputError);
}
