// The edge-extent term against hand-placed Gaussians at an object's silhouette: its value from
// the formula, its gradient against finite differences.
#include <cmath>

#include "nodes/splat/depth_edge_extent.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("edge extent: the ray extent of Gaussians on the near side of a depth edge",
          "[splat][geometry]") {
  // A 100x100 camera (focal 100) at the origin looking down +z: the left half observes an object
  // at 5 m, the right half a wall at 10 m. Edge pixels: columns 47-52 (radius 2 around 49 | 50).
  const Camera cam = test::centred_pinhole(100, 100, 100);
  const Pose pose;
  cv::Mat1f depth(100, 100, 10.f);
  depth(cv::Rect(0, 0, 50, 100)) = 5.f;
  const std::vector<DepthObservation> views = {{&cam, &pose, depth}};
  const std::vector<DepthEdgeView> edges = depth_edges(views, 0.1, 2);
  int set = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) set += edges[0].nearest(x, y) > 0;
  CHECK(set == 6 * 100);
  CHECK(edges[0].size() == 6 * 100);
  // The nearest depth in each edge pixel's 3x3 window: the object's 5 m up to column 50 (whose
  // window reaches column 49), the wall's 10 m beyond; off the edges 0. Pixel (x, y).
  CHECK(edges[0].nearest(47, 10) == 5.f);
  CHECK(edges[0].nearest(50, 10) == 5.f);
  CHECK(edges[0].nearest(51, 10) == 10.f);
  CHECK(edges[0].nearest(52, 99) == 10.f);  // the last edge pixel
  CHECK(edges[0].nearest(47, 0) == 5.f);    // the first
  CHECK(edges[0].nearest(30, 10) == 0.f);

  GaussianModel m;
  m.resize(4);
  // 0: on the object at the silhouette, pixel (50.6, 49.4): its 3x3 window reaches the object's
  //    column 49 (nearest depth 5, |5 - 5| <= 0.5): flagged. Axes x, y, z (identity rotation),
  //    scales 0.1, 0.2, 0.4.
  // 1: the same, rotated 30 degrees about y, with scales 0.3, 0.05, 0.2: flagged.
  // 2: on the object away from the edge (pixel 30): not flagged.
  // 3: at the edge but 2 m in front of the object (|3 - 5| > 0.5): not flagged.
  const float means[] = {0.03f, -0.003f, 5.f, 0.02f, 0.01f, 5.1f, -1.f, 0.f, 5.f, 0.02f, 0.f, 3.f};
  const float scales[] = {0.1f, 0.2f, 0.4f, 0.3f, 0.05f, 0.2f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
  for (int i = 0; i < 12; ++i) {
    m.means[i] = means[i];
    m.log_scales[i] = std::log(scales[i]);
  }
  const Eigen::Quaternionf rot(Eigen::AngleAxisf(0.5236f, Eigen::Vector3f::UnitY()));
  m.quats[4] = rot.w(), m.quats[5] = rot.x(), m.quats[6] = rot.y(), m.quats[7] = rot.z();

  // sigma = sqrt(sum_k s_k^2 (a_k . d)^2), d the unit ray to the mean.
  auto sigma = [&](int i, const Eigen::Matrix3d& R) {
    const Eigen::Vector3d d =
        Eigen::Vector3d(means[i * 3], means[i * 3 + 1], means[i * 3 + 2]).normalized();
    double v = 0;
    for (int a = 0; a < 3; ++a) v += std::pow(scales[i * 3 + a] * R.col(a).dot(d), 2);
    return std::sqrt(v);
  };
  const double s0 = sigma(0, Eigen::Matrix3d::Identity());
  const double s1 = sigma(1, rot.cast<double>().toRotationMatrix());
  // Gaussian 0 looks almost straight down its z axis: sigma close to its z scale 0.4.
  CHECK(s0 == Approx(0.4).epsilon(1e-3));
  // Gaussian 1's ray is near z: sqrt((0.3 sin 30)^2 + (0.2 cos 30)^2) = sqrt(0.0225 + 0.03).
  CHECK(s1 == Approx(std::sqrt(0.0525)).epsilon(1e-2));

  std::vector<float> grad;
  const double loss = depth_edge_extent_loss(m, views, edges, 0.1, &grad);
  CHECK(loss == Approx((s0 + s1) / 4).epsilon(1e-5));
  for (int k = 6; k < 12; ++k) CHECK(grad[k] == 0.f);
  // Finite differences on every log-scale.
  for (int k = 0; k < 12; ++k) {
    GaussianModel up = m, down = m;
    up.log_scales[k] += 1e-3f;
    down.log_scales[k] -= 1e-3f;
    const double fd = (depth_edge_extent_loss(up, views, edges, 0.1) -
                       depth_edge_extent_loss(down, views, edges, 0.1)) /
                      2e-3;
    CHECK(fd == Approx(grad[k]).margin(1e-4));
  }
}
