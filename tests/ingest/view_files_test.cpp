#include "nodes/ingest/view_files.hpp"

#include <cmath>

#include <opencv2/calib3d.hpp>

#include "nodes/scene/image_io.hpp"
#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;

namespace {

// Intensity-weighted centroid in gslift pixel coordinates (pixel centres at +0.5).
Eigen::Vector2d centroid(const cv::Mat& rgb) {
  double sum = 0, sx = 0, sy = 0;
  for (int y = 0; y < rgb.rows; ++y)
    for (int x = 0; x < rgb.cols; ++x) {
      const double w = rgb.at<cv::Vec3b>(y, x)[0];
      sum += w;
      sx += w * (x + 0.5);
      sy += w * (y + 0.5);
    }
  return {sx / sum, sy / sum};
}

CaptureOptions reading(bool undistort, bool crop = false, int downscale = 1) {
  CaptureOptions o;
  o.undistort = undistort;
  o.undistort_crop = crop;
  o.downscale = downscale;
  return o;
}

// A 64x48 view with k1 = 0.5 whose photo (dir/v.png) holds a blob at the distorted image of
// camera-frame point (0.3, 0.2, 1): pinhole pixel (32 + 15, 24 + 10) = kIdeal; with k1 = 0.5 the
// normalised point scales by 1 + 0.5 * 0.13 = 1.065: distorted pixel kDistorted (47.975, 34.65).
const Eigen::Vector2d kIdeal(47, 34), kDistorted(32 + 50 * 0.3 * 1.065, 24 + 50 * 0.2 * 1.065);
ViewFiles blob_view(const std::filesystem::path& dir) {
  ViewFiles f;
  f.name = "v";
  f.camera.width = 64;
  f.camera.height = 48;
  f.camera.fx = f.camera.fy = 50;
  f.camera.cx = 32;
  f.camera.cy = 24;
  f.camera.distortion = {0.5, 0, 0, 0};
  cv::Mat rgb(48, 64, CV_8UC3);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const double d2 = (Eigen::Vector2d(x + 0.5, y + 0.5) - kDistorted).squaredNorm();
      rgb.at<cv::Vec3b>(y, x) = cv::Vec3b::all(cv::saturate_cast<uchar>(255 * std::exp(-d2 / 4.5)));
    }
  write_rgb_png(dir / "v.png", rgb);
  f.rgb = dir / "v.png";
  return f;
}

}  // namespace

TEST_CASE("undistortion moves a point to its ideal pinhole projection") {
  const auto dir = test::scratch_dir("view_files_undistort");
  ViewFiles f = blob_view(dir);
  const Eigen::Vector2d& ideal = kIdeal;
  const Eigen::Vector2d& distorted = kDistorted;

  const View raw = make_views({f}, reading(false))[0];
  CHECK(raw.camera.distortion.size() == 4);
  CHECK((centroid(raw.rgb.load()) - distorted).norm() < 0.1);

  const View v = make_views({f}, reading(true))[0];
  CHECK(v.camera.distortion.empty());
  CHECK(v.camera.fx == 50);
  CHECK((centroid(v.rgb.load()) - ideal).norm() < 0.15);

  // Cropped to the valid rectangle: same focal length, the principal point and the point moved
  // by the crop's corner, and no pixel left black for want of a source.
  const cv::Rect r = undistorted_valid_rect(f.camera);
  CHECK(r.x > 0);
  CHECK(r.y > 0);
  CHECK(r.br().x < 64);
  CHECK(r.br().y < 48);
  const View cropped = make_views({f}, reading(true, true))[0];
  CHECK(cropped.camera.width == r.width);
  CHECK(cropped.camera.height == r.height);
  CHECK(cropped.camera.fx == 50);
  CHECK(cropped.camera.cx == 32 - r.x);
  CHECK((centroid(cropped.rgb.load()) - (ideal - Eigen::Vector2d(r.x, r.y))).norm() < 0.15);
  write_rgb_png(dir / "white.png", cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(255)));
  f.rgb = dir / "white.png";
  double lowest = 0;
  cv::minMaxLoc(make_views({f}, reading(true, true))[0].rgb.load().reshape(1), &lowest);
  CHECK(lowest == 255);
  // Uncropped, the corners are black: the pixels the crop removes.
  cv::minMaxLoc(make_views({f}, reading(true, false))[0].rgb.load().reshape(1), &lowest);
  CHECK(lowest == 0);
  // With a downscale the crop is a multiple of it, and the view its scaled camera.
  const View half = make_views({f}, reading(true, true, 2))[0];
  const cv::Rect r2 = undistorted_valid_rect(f.camera, 2);
  CHECK(r2.width % 2 == 0);
  CHECK(r2.height % 2 == 0);
  CHECK(half.rgb.load().size() == cv::Size(r2.width / 2, r2.height / 2));
  CHECK(half.camera.width == r2.width / 2);
}

TEST_CASE("views undistort by their own camera's maps, shared only between equal cameras") {
  // Three views of one photo: two with k1 = 0.5 (one pair of maps), one with k1 = 0.2 loaded
  // between them. Each lands where its own distortion puts the point: undistorted by k1 = 0.2
  // the blob lands near (47.53, 34.36), 0.6 px from where k1 = 0.5 puts it.
  std::vector<ViewFiles> files(3, blob_view(test::scratch_dir("view_files_shared_maps")));
  files[0].name = "a";
  files[1].name = "b";
  files[2].name = "c";
  files[0].camera.distortion = files[2].camera.distortion = {0.5, 0, 0, 0};
  files[1].camera.distortion = {0.2, 0, 0, 0};
  const std::vector<View> views = make_views(files, reading(true));
  REQUIRE(views.size() == 3);
  // Undistorting solves x (1 + k1 |x|^2) = the blob's normalised position (0.3195, 0.213): (0.3,
  // 0.2) at k1 = 0.5, (0.311, 0.207) at k1 = 0.2.
  CHECK((centroid(views[0].rgb.load()) - kIdeal).norm() < 0.15);
  CHECK((centroid(views[2].rgb.load()) - kIdeal).norm() < 0.15);
  const Eigen::Vector2d weaker = centroid(views[1].rgb.load());
  CHECK((weaker - kIdeal).norm() > 0.4);
  CHECK(weaker.x() > kIdeal.x());
  CHECK(weaker.y() > kIdeal.y());
  // The shared maps give the same pixels as a capture of that view alone.
  const cv::Mat alone = make_views({files[2]}, reading(true))[0].rgb.load();
  CHECK(cv::norm(alone, views[2].rgb.load(), cv::NORM_INF) == 0);
}

TEST_CASE("views check every file's size when it is loaded") {
  const auto dir = test::scratch_dir("view_files_size");
  ViewFiles f;
  f.name = "v";
  f.camera.width = 4;
  f.camera.height = 2;
  f.camera.fx = f.camera.fy = 1;
  f.rgb = dir / "rgb.png";
  f.gt_instance = dir / "ids.png";
  write_rgb_png(f.rgb, cv::Mat(2, 4, CV_8UC3, cv::Scalar::all(1)));
  write_label_png16(f.gt_instance, cv::Mat1i(3, 4, 5));
  const View v = make_views({f}, reading(true))[0];  // nothing is read yet
  CHECK(v.rgb.load().size() == cv::Size(4, 2));
  CHECK_THROWS_WITH(v.gt_instance.load(), Contains("ids.png") && Contains("4 x 3"));
  CHECK_FALSE(v.depth.present());
}

TEST_CASE("rational and thin-prism distortion round trip against cv::projectPoints") {
  const auto dir = test::scratch_dir("view_files_rational");
  ViewFiles f;
  f.name = "v";
  f.camera.width = 96;
  f.camera.height = 72;
  f.camera.fx = f.camera.fy = 80;
  f.camera.cx = 48;
  f.camera.cy = 36;
  // k1 k2 p1 p2 k3 k4 k5 k6 s1 s2 s3 s4: a barrel-type rational model with a thin prism, monotonic
  // out to the image corners.
  f.camera.distortion = {-0.3,  0.1,   0.001, -0.0005, -0.01, 0.05,
                         -0.01, 0.002, 0.004, -0.002,  0.003, 0.002};
  const std::vector<double>& d = f.camera.distortion;
  // The known answer: camera-frame point (0.4, -0.3, 1), by OpenCV's formula written out.
  const double x = 0.4, y = -0.3, r2 = x * x + y * y;
  const double radial = (1 + d[0] * r2 + d[1] * r2 * r2 + d[4] * r2 * r2 * r2) /
                        (1 + d[5] * r2 + d[6] * r2 * r2 + d[7] * r2 * r2 * r2);
  const double xd =
      x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x) + d[8] * r2 + d[9] * r2 * r2;
  const double yd =
      y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y + d[10] * r2 + d[11] * r2 * r2;
  // gslift pixel coordinates: OpenCV's pixel centres are at integers, gslift's at +0.5.
  const Eigen::Vector2d distorted(48 + 80 * xd, 36 + 80 * yd), ideal(48 + 80 * x, 36 + 80 * y);
  std::vector<cv::Point2d> projected;
  const cv::Mat k = (cv::Mat_<double>(3, 3) << 80, 0, 47.5, 0, 80, 35.5, 0, 0, 1);
  cv::projectPoints(std::vector<cv::Point3d>{{x, y, 1}}, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k,
                    d, projected);
  REQUIRE(std::abs(projected[0].x + 0.5 - distorted.x()) < 1e-9);
  REQUIRE(std::abs(projected[0].y + 0.5 - distorted.y()) < 1e-9);
  REQUIRE((distorted - ideal).norm() > 2);  // the distortion moves the point by pixels

  // A blob at the distorted position lands at the ideal pinhole position after undistortion.
  cv::Mat rgb(72, 96, CV_8UC3);
  for (int v = 0; v < 72; ++v)
    for (int u = 0; u < 96; ++u) {
      const double e2 = (Eigen::Vector2d(u + 0.5, v + 0.5) - distorted).squaredNorm();
      rgb.at<cv::Vec3b>(v, u) = cv::Vec3b::all(cv::saturate_cast<uchar>(255 * std::exp(-e2 / 4.5)));
    }
  write_rgb_png(dir / "v.png", rgb);
  f.rgb = dir / "v.png";
  const View v = make_views({f}, reading(true))[0];
  CHECK(v.camera.distortion.empty());
  CHECK((centroid(v.rgb.load()) - ideal).norm() < 0.15);
  const cv::Rect r = undistorted_valid_rect(f.camera);
  const View cropped = make_views({f}, reading(true, true))[0];
  CHECK((centroid(cropped.rgb.load()) - (ideal - Eigen::Vector2d(r.x, r.y))).norm() < 0.15);
  // The crop leaves no pixel without a source, and removes some.
  CHECK(r.area() < 96 * 72);
  write_rgb_png(dir / "white.png", cv::Mat(72, 96, CV_8UC3, cv::Scalar::all(255)));
  f.rgb = dir / "white.png";
  double lowest = 0;
  cv::minMaxLoc(make_views({f}, reading(true, true))[0].rgb.load().reshape(1), &lowest);
  CHECK(lowest == 255);
}
