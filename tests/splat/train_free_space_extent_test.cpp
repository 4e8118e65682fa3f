// The extent clamp against hand-placed Gaussians at an object's silhouette (numbers worked out by
// hand in the comments).
#include <cmath>

#include "nodes/splat/free_space_extent.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A 100x100 camera (focal 100) at the origin looking down +z: its left half observes an object
// at 5 m, its right half a wall at 10 m. The silhouette is the plane x = 0 at the object's depth.
struct Silhouette {
  Camera cam = test::centred_pinhole(100, 100, 100);
  Pose pose;
  cv::Mat1f depth;
  std::vector<DepthObservation> views;
  Silhouette() : depth(100, 100, 10.f) {
    depth(cv::Rect(0, 0, 50, 100)) = 5.f;
    views = {{&cam, &pose, depth}};
  }
};

GaussianModel one_gaussian(const Eigen::Vector3f& mean, const Eigen::Vector3f& scale) {
  GaussianModel m;
  m.resize(1);  // identity rotation: the axes are x, y, z
  for (int k = 0; k < 3; ++k) {
    m.means[k] = mean[k];
    m.log_scales[k] = std::log(scale[k]);
  }
  return m;
}

}  // namespace

TEST_CASE("extent clamp: the free-space test of a single point reads its own pixel") {
  const Silhouette s;
  // x = 0.5 at 5 m projects to u = 60 (wall, 10 m): 5 < 0.9 x 10, free.
  CHECK(in_observed_free_space({0.5, 0, 5}, s.views, 0.1));
  // x = -0.25 at 5 m: u = 45, on the object (5 m): not in front of it.
  CHECK_FALSE(in_observed_free_space({-0.25, 0, 5}, s.views, 0.1));
  // On the wall side but within the tolerance of the wall: 9.5 >= 0.9 x 10.
  CHECK_FALSE(in_observed_free_space({1, 0, 9.5}, s.views, 0.1));
  // Outside the image (u = 150) and behind the camera: no view says anything.
  CHECK_FALSE(in_observed_free_space({5, 0, 5}, s.views, 0.1));
  CHECK_FALSE(in_observed_free_space({0, 0, -5}, s.views, 0.1));
  // A pixel without a depth says nothing either.
  Silhouette holes;
  holes.depth(cv::Rect(50, 0, 50, 100)) = 0.f;
  CHECK_FALSE(in_observed_free_space({0.5, 0, 5}, holes.views, 0.1));
}

TEST_CASE("extent clamp: an axis reaching past the silhouette is halved until it stops there") {
  const Silhouette s;
  ExtentClampOptions o;
  CHECK_FALSE(o.active());
  o.sigmas = 1.5;
  // Centre x = -1 at 5 m (u = 30). Along x, 1.5 sigma = 1.5 reaches x = 0.5 (u = 60, the wall):
  // halved once, 0.75 reaches x = -0.25 (u = 45, the object) and stops. Along y, +-1.5 m stays
  // on the object's columns (v = 20, 80); along z, 5 +- 0.15 is not 10% in front of 5 m.
  GaussianModel m = one_gaussian({-1, 0, 5}, {1, 1, 0.1f});
  CHECK(clamp_extent_to_free_space(m, s.views, o) == 1);
  CHECK(m.log_scales[0] == Approx(std::log(0.5)).margin(1e-6));
  CHECK(m.log_scales[1] == Approx(0).margin(1e-6));
  CHECK(m.log_scales[2] == Approx(std::log(0.1)).margin(1e-6));
  CHECK(m.means[0] == -1.f);  // only the scale moves

  // Off (sigmas 0) and without views nothing changes.
  GaussianModel untouched = one_gaussian({-1, 0, 5}, {1, 1, 0.1f});
  CHECK(clamp_extent_to_free_space(untouched, s.views, ExtentClampOptions{}) == 0);
  CHECK(clamp_extent_to_free_space(untouched, {}, o) == 0);
  CHECK(untouched.log_scales[0] == Approx(0).margin(1e-6));

  // A centre in free space itself (2 m in front of the wall side) is left to free-space pruning.
  GaussianModel floating = one_gaussian({0.5, 0, 2}, {1, 1, 1});
  CHECK(clamp_extent_to_free_space(floating, s.views, o) == 0);

  // max_halvings caps the shrinking: at x = -0.05 (u = 49) even 1.5 x 2^-2 = 0.375 reaches
  // x = 0.325 (the wall), so two halvings leave log 0.25 although the overhang remains.
  o.max_halvings = 2;
  GaussianModel edge = one_gaussian({-0.05f, 0, 5}, {1, 0.01f, 0.01f});
  CHECK(clamp_extent_to_free_space(edge, s.views, o) == 1);
  CHECK(edge.log_scales[0] == Approx(std::log(0.25)).margin(1e-6));
}
