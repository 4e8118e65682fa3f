// Pinhole cameras and poses. Conventions (the same as COLMAP and OpenCV): camera axes x right,
// y down, z forward; poses are world-to-camera (x_cam = R x_world + t); pixel (0,0) is the corner
// of the top-left pixel, so the centre of pixel (u,v) is (u+0.5, v+0.5).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace gslift {

struct Camera {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  // OpenCV's (k1, k2, p1, p2[, k3[, k4, k5, k6[, s1, s2, s3, s4]]]), empty for a pinhole. Stages
  // that need undistorted pixels undistort images at ingest, so the rest sees a pinhole.
  std::vector<double> distortion;

  Eigen::Matrix3d K() const;
  // Scaled copy for a resized image (intrinsics scale with the pixel grid).
  Camera scaled(double s) const;
};

// The most pixels an image gslift reads, renders or allocates for may have: 2^26 (67 Mpx, e.g.
// 8192 x 8192, twice an 8K frame, more than any operating-room camera). Above it a corrupt or
// hostile header costs gigabytes before anything fails: a 30000 x 30000 camera (0.9 Gpx) made
// splat.render allocate 24 GB of per-pixel state until the kernel killed it.
constexpr long long kMaxImagePixels = 1LL << 26;

// Throws InputError "<where>: ..." unless width and height are positive and their product is at
// most kMaxImagePixels. Takes 64-bit sizes so that a header's value is checked before it is
// narrowed to int.
void check_image_size(long long width, long long height, const std::string& where);

// check_image_size, focal lengths finite and positive, a finite principal point and 0, 4, 5, 8
// or 12 finite distortion coefficients: what every reader checks before a camera enters a Capture.
void check_camera(const Camera& camera, const std::string& where);

struct Pose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // world -> camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      // world -> camera translation

  static Pose from_camera_to_world(const Eigen::Matrix4d& c2w);
  Eigen::Matrix4d world_to_camera() const;
  Eigen::Vector3d centre() const { return -R.transpose() * t; }
  Eigen::Vector3d to_camera(const Eigen::Vector3d& x) const { return R * x + t; }
};

}  // namespace gslift
