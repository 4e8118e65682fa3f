// Ray depths (the depth of a Gaussian's density maximum along each pixel's ray) against their
// closed forms, and what they change in the free-space footprint test and the line-of-sight loss:
// a slanted surface lying on its prior is on it at every pixel, where its centre's depth puts the
// far side of its footprint behind the prior and the near side in front of it.
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "nodes/splat/free_space.hpp"
#include "nodes/splat/line_of_sight_loss.hpp"
#include "nodes/splat/ray_depth.hpp"
#include "tests/splat/pinhole_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// The plane through the point 4 m down the optical axis that leans back to the right:
// z = 4 + 0.5 x, normal n = (-0.5, 0, 1) / |.|.
const Eigen::Vector3d kNormal = Eigen::Vector3d(-0.5, 0, 1).normalized();
const Eigen::Vector3d kPoint(0, 0, 4);

// The camera depth at which pixel (u, v)'s ray meets that plane.
double plane_depth(const Camera& cam, double u, double v) {
  const Eigen::Vector3d r((u + 0.5 - cam.cx) / cam.fx, (v + 0.5 - cam.cy) / cam.fy, 1);
  return kNormal.dot(kPoint) / kNormal.dot(r);
}

// One disc in that plane at kPoint: in-plane scale `in_plane`, 1e-4 m thick, opacity 0.9.
GaussianModel disc_on_plane(double in_plane) {
  GaussianModel m;
  m.resize(1);
  for (int k = 0; k < 3; ++k) m.means[k] = float(kPoint[k]);
  const Eigen::Quaterniond q =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), kNormal);
  m.quats[0] = float(q.w()), m.quats[1] = float(q.x()), m.quats[2] = float(q.y()),
  m.quats[3] = float(q.z());
  m.log_scales[0] = m.log_scales[1] = float(std::log(in_plane));
  m.log_scales[2] = float(std::log(1e-4));
  m.opacity_logits[0] = float(std::log(0.9 / 0.1));
  return m;
}

// The plane as a depth prior of the scene's view.
cv::Mat1f plane_prior(const Camera& cam) {
  cv::Mat1f depth(cam.height, cam.width);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) depth(v, u) = float(plane_depth(cam, u, v));
  return depth;
}

}  // namespace

TEST_CASE(
    "ray depth: a flat Gaussian's follows its plane, an isotropic one's is its centre on "
    "the ray",
    "[splat][geometry]") {
  const test::PinholeScene scene;
  const Camera& cam = scene.cam;
  const GaussianModel disc = disc_on_plane(0.3);
  const RenderOutput out = scene.forward(disc);
  // Clamped to the centre's depth +- min(3 x largest scale, 10%): 4 +- 0.4 for this disc.
  const RayDepths ray(disc, cam, scene.pose, out.state->projections);
  alignas(64) float z[kLanes];
  for (int y : {10, 15, 20}) {
    ray.row(0, y, 8, z);
    for (int x = 0; x < kLanes; ++x) {
      INFO("pixel " << 8 + x << ", " << y);
      CHECK(z[x] == Approx(std::clamp(plane_depth(cam, 8 + x, y), 3.6, 4.4)).epsilon(1e-4));
    }
  }
  // Both sides of the row were checked: unclamped near the centre, clamped beyond.
  CHECK(plane_depth(cam, 8, 15) < 3.6);
  CHECK(plane_depth(cam, 23, 15) > 4.1);

  // Isotropic (P = I / s^2): t* = (r . m) / (r . r), the centre projected onto the ray.
  GaussianModel ball;
  ball.resize(1);
  scene.place(ball, 0, 14.5, 11.5, 3.0, 0.2, 0.8);
  const RayDepths ball_ray(ball, cam, scene.pose, scene.forward(ball).state->projections);
  const Eigen::Vector3d m(ball.means[0], ball.means[1], ball.means[2]);
  ball_ray.row(0, 18, 16, z);
  for (int x = 0; x < kLanes; ++x) {
    const Eigen::Vector3d r((16 + x + 0.5 - cam.cx) / cam.fx, (18 + 0.5 - cam.cy) / cam.fy, 1);
    CHECK(z[x] == Approx(std::clamp(r.dot(m) / r.dot(r), 2.7, 3.3)).epsilon(1e-5));
  }
  // The clamp: 3 - 3 x 0.1 for this one, 4 - 10% for the disc.
  CHECK(ball_ray.nearest(0) == Approx(2.7).epsilon(1e-6));
  CHECK(ray.nearest(0) == Approx(3.6).epsilon(1e-6));
}

TEST_CASE("ray depth: a slanted surface on its prior is on the surface at every pixel",
          "[splat][geometry]") {
  const test::PinholeScene scene;
  const cv::Mat1f prior = plane_prior(scene.cam);
  const std::vector<DepthObservation> views = {{&scene.cam, &scene.pose, prior}};
  // 2 m across at 4 m: about 6 pixels either side of its centre, where the plane is 7-8% nearer
  // or farther than there (inside the clamp).
  const GaussianModel disc = disc_on_plane(0.2);
  // By its centre's depth the near side of the footprint is hidden behind the prior (14% of it
  // at a 2% margin); by its ray depths none of it is.
  const FootprintDepth by_centre = footprint_behind(disc, views, 0.02);
  const FootprintDepth by_ray = footprint_behind(disc, views, 0.02, true);
  REQUIRE(by_centre.observed[0] > 10);
  CHECK(by_ray.observed[0] == Approx(by_centre.observed[0]));
  INFO("behind by centre " << by_centre.behind[0] / by_centre.observed[0]);
  CHECK(by_centre.behind[0] > 0.1 * by_centre.observed[0]);
  CHECK(by_ray.behind[0] == 0);
  // The same for the weight it draws, and the near side in front of the prior.
  const LineOfSightWeights w_centre = line_of_sight_weights(disc, views, 0.02);
  const LineOfSightWeights w_ray = line_of_sight_weights(disc, views, 0.02, true);
  CHECK(w_centre.free_space[0] > 0.1 * (w_centre.free_space[0] + w_centre.on_surface[0]));
  CHECK(w_ray.free_space[0] == 0);
  CHECK(w_ray.behind[0] == 0);
  CHECK(w_ray.on_surface[0] == Approx(w_centre.free_space[0] + w_centre.on_surface[0]));
  // The line-of-sight loss: the near side's opacity counts as drawn in front of the prior by the
  // centre's depth, and by the ray depths only the far tail of the footprint past the clamp
  // (this render has no min_alpha: it reaches 3 sigma).
  const RenderOutput out = scene.forward(disc);
  CHECK(line_of_sight_loss(disc, scene.cam, scene.pose, prior, out, 0.02) > 0.001);
  CHECK(line_of_sight_loss(disc, scene.cam, scene.pose, prior, out, 0.02, 1.0, nullptr, true) <
        1e-6);
}

TEST_CASE(
    "ray depth: where every Gaussian is clearly in front, the line-of-sight loss and its "
    "gradient are the centre depth's",
    "[splat][geometry]") {
  const test::PinholeScene scene;
  // A wall at 4 m: two anisotropic, rotated Gaussians at 2 and 2.2 m are in front of it at every
  // pixel by either depth (ray depths stay within 10% of the centre's).
  const cv::Mat1f wall(30, 40, 4.f);
  GaussianModel m;
  m.resize(2);
  scene.place(m, 0, 15.5, 14.5, 2.0, 0.1, 0.6);
  scene.place(m, 1, 22.5, 16.5, 2.2, 0.1, 0.7);
  test::PinholeScene::twist(m);
  const RenderOutput out = scene.forward(m);
  ModelGrads by_centre, by_ray;
  by_centre.reset(m);
  by_ray.reset(m);
  const double centre =
      line_of_sight_loss(m, scene.cam, scene.pose, wall, out, 0.03, 1.0, &by_centre);
  const double ray =
      line_of_sight_loss(m, scene.cam, scene.pose, wall, out, 0.03, 1.0, &by_ray, true);
  CHECK(centre > 0.01);
  CHECK(ray == Approx(centre).epsilon(1e-6));
  for (size_t k = 0; k < by_centre.means.size(); ++k)
    CHECK(by_ray.means[k] == Approx(by_centre.means[k]).epsilon(1e-5).margin(1e-9));
  for (size_t k = 0; k < by_centre.quats.size(); ++k)
    CHECK(by_ray.quats[k] == Approx(by_centre.quats[k]).epsilon(1e-5).margin(1e-9));
  for (size_t k = 0; k < 2; ++k)
    CHECK(by_ray.opacity_logits[k] == Approx(by_centre.opacity_logits[k]).epsilon(1e-5));
}

TEST_CASE(
    "ray depth: a slanted disc that crosses a wall's cut draws its opacity in front of it only "
    "where its ray depth is nearer than the cut",
    "[splat][geometry]") {
  const test::PinholeScene scene;
  // The disc leans back to the right (z = 4 + 0.5 x); a fronto-parallel wall at 4 m, cut 3% in
  // front of it: the disc's left part is in front of the cut, its right part behind it, and the
  // tile rows of the middle tile hold both (the line-of-sight pass skips rows with no pixel in
  // front, and must keep the others).
  const GaussianModel disc = disc_on_plane(0.3);
  const cv::Mat1f wall(scene.cam.height, scene.cam.width, 4.f);
  const RenderOutput out = scene.forward(disc);
  const RayDepths ray(disc, scene.cam, scene.pose, out.state->projections);
  // One Gaussian: the opacity drawn in front of pixel p's cut is its alpha there (the render's
  // alpha) where its ray depth is nearer than the cut, else nothing.
  double expected = 0;
  int in_front = 0, behind = 0;
  alignas(64) float z[kLanes];
  for (int y = 0; y < wall.rows; ++y)
    for (int x0 = 0; x0 < wall.cols; x0 += kLanes) {
      ray.row(0, y, x0, z);
      for (int x = x0; x < std::min(x0 + kLanes, wall.cols); ++x) {
        const float a = out.alpha[size_t(y) * wall.cols + x];
        if (a <= 0) continue;
        const bool front = z[x - x0] < float((1 - 0.03) * 4.0);  // the loss's cut, rounded alike
        expected += front ? a : 0.0;
        (front ? in_front : behind) += 1;
      }
    }
  REQUIRE(in_front > 20);
  REQUIRE(behind > 20);
  const double loss =
      line_of_sight_loss(disc, scene.cam, scene.pose, wall, out, 0.03, 1.0, nullptr, true);
  CHECK(loss == Approx(expected / (wall.rows * wall.cols)).epsilon(1e-5));
}
