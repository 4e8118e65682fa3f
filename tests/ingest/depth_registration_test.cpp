#include "nodes/ingest/depth_registration.hpp"

#include <cmath>

#include "tests/test_support.hpp"

using namespace gslift;

namespace {

Camera pinhole_camera(int w, int h, double f) {
  Camera c;
  c.width = w;
  c.height = h;
  c.fx = c.fy = f;
  c.cx = w / 2.0;
  c.cy = h / 2.0;
  return c;
}

// z of the ray through the centre of pixel (u, v) of a pinhole camera meeting the plane
// n . x = d (camera frame).
double plane_z(const Camera& c, int u, int v, const Eigen::Vector3d& n, double d) {
  const Eigen::Vector3d ray((u + 0.5 - c.cx) / c.fx, (v + 0.5 - c.cy) / c.fy, 1);
  return d / n.dot(ray);
}

}  // namespace

TEST_CASE("depth of a tilted plane registers to the colour camera's z") {
  // Depth camera 48 x 36 at f 40; colour camera 96 x 72 at f 90 (a narrower field at twice the
  // resolution), 5 cm to the side, 1 cm forward and turned 4 degrees about y.
  DepthSensor sensor;
  sensor.camera = pinhole_camera(48, 36, 40);
  sensor.depth_to_colour.R = Eigen::AngleAxisd(4 * M_PI / 180, Eigen::Vector3d::UnitY()).matrix();
  sensor.depth_to_colour.t = {-0.05, 0, -0.01};
  const Camera colour = pinhole_camera(96, 72, 90);
  // The plane z = 2 + 0.3 x (depth frame): n . x = d with n = (-0.3, 0, 1), d = 2.
  const Eigen::Vector3d n_depth(-0.3, 0, 1);
  const double d_depth = 2;
  cv::Mat depth(36, 48, CV_32FC1);
  for (int v = 0; v < 36; ++v)
    for (int u = 0; u < 48; ++u)
      depth.at<float>(v, u) = static_cast<float>(plane_z(sensor.camera, u, v, n_depth, d_depth));
  // The same plane in the colour frame: x_d = R^T (x_c - t), so (R n) . x_c = d + (R n) . t.
  const Eigen::Vector3d n_colour = sensor.depth_to_colour.R * n_depth;
  const double d_colour = d_depth + n_colour.dot(sensor.depth_to_colour.t);

  const cv::Mat reg = register_depth(depth, sensor, colour);
  REQUIRE(reg.size() == cv::Size(96, 72));
  int covered = 0, should = 0;
  double worst = 0;
  for (int v = 0; v < 72; ++v)
    for (int u = 0; u < 96; ++u) {
      const double z = plane_z(colour, u, v, n_colour, d_colour);
      // The colour pixel's surface point seen by the depth camera, in its pixel coordinates:
      // inside the hull of the depth pixel centres (less a pixel), it must be covered.
      const Eigen::Vector3d x = (Eigen::Vector3d((u + 0.5 - 48) / 90, (v + 0.5 - 36) / 90, 1) * z);
      const Eigen::Vector3d xd =
          sensor.depth_to_colour.R.transpose() * (x - sensor.depth_to_colour.t);
      const double du = 40 * xd.x() / xd.z() + 24, dv = 40 * xd.y() / xd.z() + 18;
      const bool inside = du > 1.5 && du < 46.5 && dv > 1.5 && dv < 34.5;
      should += inside;
      const float r = reg.at<float>(v, u);
      if (r == 0) {
        CHECK(!inside);
        continue;
      }
      ++covered;
      worst = std::max(worst, std::abs(r - z) / z);
      CHECK(du > 0);  // nothing lands outside the depth camera's view
      CHECK(du < 48);
    }
  CHECK(should > 3000);  // most of the colour image sees the plane inside the depth view
  CHECK(covered >= should);
  CHECK(worst < 1e-5);  // perspective-correct: exact for a plane up to float rounding
}

TEST_CASE("depth registration keeps the nearest surface and leaves holes as holes") {
  // Colour 10 cm to the right of the depth camera (x_colour = x_depth - 0.1): from there a box
  // at 1 m hides part of the wall at 2 m that the depth camera sees beside the box.
  DepthSensor sensor;
  sensor.camera = pinhole_camera(64, 48, 50);
  sensor.depth_to_colour.t = {-0.1, 0, 0};
  const Camera colour = sensor.camera;
  cv::Mat depth(48, 64, CV_32FC1, cv::Scalar(2.0f));
  depth(cv::Rect(24, 16, 16, 16)).setTo(1.0f);  // the box
  depth(cv::Rect(0, 40, 64, 8)).setTo(0.0f);    // no measurement in the bottom rows

  const cv::Mat reg = register_depth(depth, sensor, colour);
  // The box's pixels move 50 * 0.1 / 1 = 5 pixels left, the wall's 2.5: columns 19..34 of the
  // box, whose left edge now covers wall that the depth camera saw at columns 19..23 (moved to
  // 16.5..21.5): the box wins there.
  for (int u = 20; u <= 33; ++u) CHECK(reg.at<float>(24, u) == Approx(1.0f));
  CHECK(reg.at<float>(24, 10) == Approx(2.0f));
  // Right of the box the wall the depth camera could not see behind it is a hole, not smeared:
  // box pixels end at 34.5, the wall seen right of the box starts at 40.5 - 2.5 = 38.
  CHECK(reg.at<float>(24, 36) == 0);
  CHECK(reg.at<float>(24, 45) == Approx(2.0f));
  // No depth, no registered depth.
  for (int u = 0; u < 64; ++u) CHECK(reg.at<float>(44, u) == 0);
}
