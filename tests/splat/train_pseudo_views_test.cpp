// Depth-warped pseudo-views: the warp of a known plane, the z-buffer, the interpolated pose and
// the masked L1 loss that supervises them.
#include <cmath>

#include "nodes/splat/losses.hpp"
#include "nodes/splat/pseudo_views.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A 40x30 view of a wall at depth 2 whose colour encodes the world x and y of each pixel's point.
struct Wall {
  Camera camera = test::centred_pinhole(40, 30, 40);
  Pose pose;
  cv::Mat rgb = cv::Mat(30, 40, CV_32FC3);
  cv::Mat depth = cv::Mat(30, 40, CV_32FC1, cv::Scalar(2.0));
  Wall() {
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x) {
        const double wx = (x + 0.5 - 20) / 40 * 2, wy = (y + 0.5 - 15) / 40 * 2;
        rgb.at<cv::Vec3f>(y, x) = cv::Vec3f(float(0.5 + wx / 4), float(0.5 + wy / 4), 0.25f);
      }
  }
};

}  // namespace

TEST_CASE("pseudo-view: warping a wall into its own camera gives back its image") {
  const Wall w;
  const PseudoView p = warp_into_view(w.camera, w.pose, {{&w.camera, &w.pose, w.rgb, w.depth}});
  CHECK(cv::countNonZero(p.valid) == 40 * 30);
  CHECK(cv::norm(p.rgb, w.rgb, cv::NORM_INF) == 0);
  CHECK(cv::norm(p.depth, w.depth, cv::NORM_INF) == 0);
}

TEST_CASE("pseudo-view: a camera moved sideways sees the wall's points where they project") {
  const Wall w;
  // Moved 0.5 m along +x: the point of source pixel (x, y) lands 10 pixels to the left
  // (u = 40 (X - 0.5) / 2 + 20), so target pixel (u, y) shows source pixel (u + 10, y); the right
  // 10 columns see wall the source never saw.
  Pose moved;
  moved.t = Eigen::Vector3d(-0.5, 0, 0);
  const PseudoView p = warp_into_view(w.camera, moved, {{&w.camera, &w.pose, w.rgb, w.depth}});
  for (int y = 0; y < 30; ++y)
    for (int u = 0; u < 40; ++u) {
      INFO("pixel " << u << ", " << y);
      if (u < 30) {
        REQUIRE(p.valid(y, u) == 1);
        CHECK(p.rgb.at<cv::Vec3f>(y, u) == w.rgb.at<cv::Vec3f>(y, u + 10));
        CHECK(p.depth.at<float>(y, u) == Approx(2.0));
      } else {
        CHECK(p.valid(y, u) == 0);
      }
    }
}

TEST_CASE("pseudo-view: the nearer surface wins, and a far one seen through a gap is dropped") {
  Wall w;
  // A box at depth 1 covering the source's centre 10x10 pixels, coloured white.
  w.depth(cv::Rect(15, 10, 10, 10)) = 1.0;
  w.rgb(cv::Rect(15, 10, 10, 10)) = cv::Scalar(1, 1, 1);
  // Seen from 2x farther back, the box covers half as many pixels: the z-buffer keeps it over the
  // wall behind it, and no wall pixel survives inside the box's image.
  Pose back;
  back.t = Eigen::Vector3d(0, 0, 2);  // camera 2 m behind the source
  const PseudoView p = warp_into_view(w.camera, back, {{&w.camera, &w.pose, w.rgb, w.depth}});
  // The box (half-width 5 px x 1 m / 40 = 0.125 m, at z = 3 from here) covers pixels 20 +- 1.7.
  CHECK(p.valid(15, 20) == 1);
  CHECK(p.depth.at<float>(15, 20) == Approx(3.0));
  CHECK(p.rgb.at<cv::Vec3f>(15, 20) == cv::Vec3f(1, 1, 1));
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      if (p.valid(y, x) && p.depth.at<float>(y, x) > 3.5f) {
        // A wall pixel: no box pixel (depth 3) within 2 pixels of it.
        for (int yy = std::max(y - 2, 0); yy <= std::min(y + 2, 29); ++yy)
          for (int xx = std::max(x - 2, 0); xx <= std::min(x + 2, 39); ++xx)
            CHECK_FALSE(std::abs(p.depth.at<float>(yy, xx) - 3.0f) < 0.01f);
      }
}

TEST_CASE("pseudo-view poses lie halfway between camera pairs that face the same way") {
  Pose a, b, c;
  b.R = Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitY()).toRotationMatrix();
  b.t = -b.R * Eigen::Vector3d(2, 0, 0);                                       // centre (2, 0, 0)
  c.R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();  // facing back
  const Pose mid = interpolate_pose(a, b, 0.5);
  CHECK((mid.centre() - Eigen::Vector3d(1, 0, 0)).norm() < 1e-12);
  CHECK(Eigen::AngleAxisd(mid.R).angle() == Approx(0.3));
  const Camera cam = test::centred_pinhole(8, 6, 8);
  const cv::Mat rgb(6, 8, CV_32FC3, cv::Scalar::all(0.5)), depth(6, 8, CV_32FC1, cv::Scalar(2));
  const std::vector<PseudoView> views = pseudo_views_between(
      {{&cam, &a, rgb, depth}, {&cam, &b, rgb, depth}, {&cam, &c, rgb, depth}}, 100, 0.5);
  // a-b (34 degrees) yes; a-c and b-c (180 and 146 degrees) no.
  REQUIRE(views.size() == 1);
  CHECK(views[0].camera.width == 4);
  CHECK((views[0].pose.centre() - Eigen::Vector3d(1, 0, 0)).norm() < 1e-12);
}

TEST_CASE("masked L1: mean over the masked pixels and channels, gradient by hand") {
  cv::Mat r(1, 3, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5)), t(1, 3, CV_32FC3, cv::Scalar(0, 1, 0.5));
  cv::Mat1b mask(1, 3, uchar(1));
  mask(0, 2) = 0;
  cv::Mat grad;
  // Counted: 2 pixels x 3 channels, |d| = 0.5, 0.5, 0 each: sum 2 over 6, gradient sign / 6.
  CHECK(masked_l1_loss(r, t, mask, &grad) == Approx(1.0 / 3));
  CHECK(grad.at<cv::Vec3f>(0, 0)[0] == Approx(1.0 / 6));
  CHECK(grad.at<cv::Vec3f>(0, 0)[1] == Approx(-1.0 / 6));
  CHECK(grad.at<cv::Vec3f>(0, 0)[2] == 0.f);
  CHECK(grad.at<cv::Vec3f>(0, 2) == cv::Vec3f(0, 0, 0));
  CHECK(masked_l1_loss(r, t, cv::Mat1b(1, 3, uchar(0))) == 0);
}
