#include "nodes/ingest/capture_loader.hpp"

#include <algorithm>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "nodes/scene/image_io.hpp"
#include "runtime/node.hpp"
#include "tests/ingest/small_capture.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// Median |depth of frame b at the reprojection of frame a's pixels - their depth in b|, over a
// grid of valid pixels: small only when intrinsics, depth scale and pose convention agree.
double median_reprojection_depth_error(const View& a, const View& b) {
  const cv::Mat da = a.depth.load(), db = b.depth.load();
  const Eigen::Matrix3d ka_inv = a.camera.K().inverse();
  std::vector<double> errors;
  for (int v = 0; v < da.rows; v += 16)
    for (int u = 0; u < da.cols; u += 16) {
      const float d = da.at<float>(v, u);
      if (d <= 0) continue;
      const Eigen::Vector3d xa = d * (ka_inv * Eigen::Vector3d(u + 0.5, v + 0.5, 1));
      const Eigen::Vector3d world = a.pose.R.transpose() * (xa - a.pose.t);
      const Eigen::Vector3d xb = b.pose.to_camera(world);
      if (xb.z() <= 0) continue;
      const Eigen::Vector3d pb = b.camera.K() * xb / xb.z();
      const int ub = static_cast<int>(pb.x()), vb = static_cast<int>(pb.y());
      if (ub < 0 || vb < 0 || ub >= db.cols || vb >= db.rows) continue;
      const float dbv = db.at<float>(vb, ub);
      if (dbv > 0) errors.push_back(std::abs(dbv - xb.z()));
    }
  REQUIRE(errors.size() > 50);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}

void check_depth_range(const View& v, float lo, float hi) {
  const cv::Mat d = v.depth.load();
  REQUIRE(d.type() == CV_32FC1);
  double mn = 0, mx = 0;
  cv::minMaxLoc(d, &mn, &mx, nullptr, nullptr, d > 0);
  CHECK(mn > lo);
  CHECK(mx < hi);
}

}  // namespace

TEST_CASE("capture.yaml folder: views, depth in metres, ground truth, held-out views") {
  const auto dir = test::write_small_capture("capture_yaml", "held_out: [cam_01]\n");
  const Capture c = load_capture(dir);
  CHECK(c.name == "small");
  REQUIRE(c.views.size() == 3);
  CHECK(c.views[1].name == "cam_01");
  CHECK(c.test_views() == std::vector<int>{1});
  CHECK(c.points.size() == 1);
  CHECK((c.views[2].pose.centre() - Eigen::Vector3d(-2, 0, -2)).norm() < 1e-12);
  const cv::Mat rgb = c.views[2].rgb.load();
  CHECK(rgb.at<cv::Vec3b>(0, 0) == cv::Vec3b(2, 4, 6));
  CHECK(c.views[2].depth.load().at<float>(5, 7) == Approx(3.5));
  CHECK(c.views[1].gt_instance.load().at<int>(0, 0) == 301);
  CHECK_FALSE(c.views[0].gt_depth.present());
  CHECK(c.classes.at(2) == "surgeon");
  CHECK(c.instance_class.at(300) == 1);

  SECTION("downscale halves images and intrinsics") {
    const Capture h = load_capture(dir, {0, false, 2});
    CHECK(h.views[0].camera.width == 4);
    CHECK(h.views[0].camera.fx == 5);
    CHECK(h.views[0].rgb.load().size() == cv::Size(4, 3));
    CHECK(h.views[0].depth.load().at<float>(2, 3) == Approx(1.5));
    CHECK(h.views[0].gt_instance.load().at<int>(2, 3) == 300);
  }
  SECTION("depth of the wrong size fails when it is loaded, naming the file") {
    write_depth_png_mm(dir / "depth/cam_00.png", cv::Mat1f(5, 8, 1.f));
    const Capture bad = load_capture(dir);
    CHECK_THROWS_AS(bad.views[0].depth.load(), InputError);
    CHECK_THROWS_WITH(bad.views[0].depth.load(), Contains("cam_00.png") && Contains("8 x 5"));
  }
  SECTION("an 8-bit ground-truth label map fails when it is loaded, naming the file") {
    cv::imwrite((dir / "gt/instance/cam_01.png").string(), cv::Mat1b(6, 8, uchar(3)));
    CHECK_THROWS_WITH(load_capture(dir).views[1].gt_instance.load(),
                      Contains("cam_01.png") && Contains("8-bit"));
  }
  SECTION("a listed image that is missing is an error unless skipped") {
    fs::remove(dir / "images/cam_02.png");
    CHECK_THROWS_WITH(load_capture(dir), Contains("cam_02.png") && Contains("missing"));
    CHECK(load_capture(dir, {0, true, 1}).views.size() == 2);
  }
}

TEST_CASE("capture.yaml errors name the file") {
  SECTION("wrong format") {
    const auto dir = test::write_small_capture("capture_bad_format", "");
    std::ofstream(dir / "capture.yaml") << "format: gslift.capture/v9\n";
    CHECK_THROWS_WITH(load_capture(dir), Contains("capture.yaml") && Contains("v9"));
  }
  SECTION("unknown held-out view") {
    const auto dir = test::write_small_capture("capture_bad_holdout", "held_out: [cam_07]\n");
    CHECK_THROWS_WITH(load_capture(dir), Contains("capture.yaml") && Contains("cam_07"));
  }
  SECTION("not a capture") {
    const auto dir = test::scratch_dir("capture_empty");
    CHECK_THROWS_WITH(load_capture(dir), Contains("transforms.json") && Contains("sparse/0"));
  }
}

TEST_CASE("holdout_every marks every n-th view when capture.yaml names none") {
  const auto dir = test::write_small_capture("capture_holdout_every", "");
  CHECK(load_capture(dir, {2, false, 1}).test_views() == std::vector<int>{0, 2});
  CHECK(load_capture(dir).test_views().empty());
}

TEST_CASE("train_every keeps every n-th view for training and holds out the others") {
  // 3 views: train_every 3 trains on cam_00 alone; cam_01 and cam_02 stay, held out.
  const auto dir = test::write_small_capture("capture_train_every", "");
  CaptureOptions o;
  o.train_every = 3;
  const Capture c = load_capture(dir, o);
  CHECK(c.views.size() == 3);
  CHECK(c.train_views() == std::vector<int>{0});
  CHECK(c.test_views() == std::vector<int>{1, 2});
  // With holdout_every 2 as well (cam_00 and cam_02 held out), no view is left to train on.
  o.holdout_every = 2;
  o.train_every = 2;
  CHECK(load_capture(dir, o).train_views().empty());
  o.train_every = 0;
  CHECK_THROWS_WITH(load_capture(dir, o), Contains("train_every"));
}

TEST_CASE("NeRF transforms.json: intrinsics, per-frame overrides, missing images") {
  const auto dir = test::scratch_dir("nerf_fixture");
  write_rgb_png(dir / "imgs/a.png", cv::Mat(4, 6, CV_8UC3, cv::Scalar::all(9)));
  write_rgb_png(dir / "imgs/b.png", cv::Mat(4, 6, CV_8UC3, cv::Scalar::all(9)));
  const double half_pi = 1.5707963267948966;
  std::ofstream(dir / "transforms.json") << R"({"camera_angle_x": )" << half_pi << R"(,
    "k1": 0.1, "frames": [
      {"file_path": "./imgs/a", "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,5],[0,0,0,1]]},
      {"file_path": "imgs/absent.png", "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]},
      {"file_path": "imgs/b.png", "fl_x": 7, "cx": 2.5, "k1": 0,
       "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
  const Capture c = load_capture(dir, {0, false, 1, false});  // keep the distortion
  REQUIRE(c.views.size() == 2);
  const Camera& a = c.views[0].camera;
  CHECK(a.width == 6);         // from the image: the file gives no w/h
  CHECK(a.fx == Approx(3.0));  // 6 / 2 / tan(45 deg)
  CHECK(a.fy == Approx(3.0));
  CHECK(a.cx == 3.0);
  CHECK(a.distortion == std::vector<double>{0.1, 0, 0, 0});
  // OpenGL camera 5 units up +z looking down -z: in OpenCV axes the origin is 5 units ahead.
  CHECK((c.views[0].pose.to_camera(Eigen::Vector3d::Zero()) - Eigen::Vector3d(0, 0, 5)).norm() <
        1e-12);
  // World +y (OpenGL camera up) is image up, i.e. camera -y.
  CHECK(c.views[0].pose.R(1, 1) == -1);
  CHECK(c.views[1].camera.fx == 7);
  CHECK(c.views[1].camera.cx == 2.5);
  CHECK(c.views[1].camera.distortion.empty());

  std::ofstream(dir / "transforms.json")
      << R"({"camera_model": "OPENCV_FISHEYE", "fl_x": 3, "frames": [{"file_path": "imgs/a.png",)"
      << R"( "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
  CHECK_THROWS_WITH(load_capture(dir), Contains("transforms.json") && Contains("OPENCV_FISHEYE"));
  std::ofstream(dir / "transforms.json") << R"({"frames": [{"file_path": "imgs/a.png"}]})";
  CHECK_THROWS_WITH(load_capture(dir), Contains("transforms.json frame 0"));
  std::ofstream(dir / "transforms.json") << R"({"frames": [)";
  CHECK_THROWS_WITH(load_capture(dir), Contains("transforms.json") && Contains("invalid JSON"));
}

TEST_CASE("DTU scan 24 COLMAP text model: missing odd views") {
  GSLIFT_REQUIRE_SHARED_DATA("dtu_scan24");
  const auto model = test::shared_data("dtu_scan24/colmap");
  CHECK_THROWS_WITH(load_capture(model), Contains("000001.png") && Contains("missing"));
  const Capture c = load_capture(model, {8, true, 4});
  REQUIRE(c.views.size() == 25);
  CHECK(c.views[1].name == "000002");
  CHECK(c.views[0].camera.width == 400);
  CHECK(c.views[0].camera.fx == Approx(2892.330631 / 4));
  CHECK(c.test_views() == std::vector<int>{0, 8, 16, 24});
  const cv::Mat rgb = c.views[0].rgb.load();
  CHECK(rgb.size() == cv::Size(400, 300));
  CHECK(rgb.type() == CV_8UC3);
}

TEST_CASE("DTU scan 24 workspace: binary sparse/0 is found first") {
  GSLIFT_REQUIRE_SHARED_DATA("dtu_scan24");
  const Capture c = load_capture(test::shared_data("dtu_scan24"), {0, true, 1, false});
  CHECK(c.name == "dtu_scan24");
  CHECK(c.views.size() == 25);
  CHECK(c.points.size() == 34673);
  CHECK(c.views[0].camera.distortion.size() == 4);
  // Undistorted by default: a pinhole camera, cropped to the valid rectangle (k1 > 0 leaves
  // 2-3 px of black along the 400 x 300 border); uncropped, images of the captured size.
  const Capture u = load_capture(test::shared_data("dtu_scan24"), {0, true, 4});
  CHECK(u.views[0].camera.distortion.empty());
  CHECK(u.views[0].rgb.load().size() == cv::Size(396, 297));
  CHECK(u.views[0].camera.width == 396);
  const cv::Mat rgb = u.views[0].rgb.load();
  CHECK(rgb.at<cv::Vec3b>(0, 0) != cv::Vec3b(0, 0, 0));  // the corners have a source
  CHECK(rgb.at<cv::Vec3b>(296, 395) != cv::Vec3b(0, 0, 0));
  CaptureOptions uncropped{0, true, 4};
  uncropped.undistort_crop = false;
  const Capture k = load_capture(test::shared_data("dtu_scan24"), uncropped);
  CHECK(k.views[0].rgb.load().size() == cv::Size(400, 300));
  const cv::Mat black = k.views[0].rgb.load();  // corners mapped from outside the photo
  CHECK(black.at<cv::Vec3b>(0, 0) == cv::Vec3b(0, 0, 0));
  CHECK(black.at<cv::Vec3b>(299, 399) == cv::Vec3b(0, 0, 0));
}

TEST_CASE("NeRF lego and instant-ngp fox") {
  GSLIFT_REQUIRE_SHARED_DATA("nerf_synthetic_lego_subset");
  const Capture lego = load_capture(test::shared_data("nerf_synthetic_lego_subset"));
  REQUIRE(lego.views.size() == 25);
  CHECK(lego.views[1].name == "r_4");
  CHECK(lego.views[0].camera.fx == Approx(400 / std::tan(0.6911112070083618 / 2)));
  CHECK(lego.views[0].camera.cx == 400);
  for (const auto& v : lego.views) {
    // Every Blender camera looks at the object at the origin from ~4 units.
    const Eigen::Vector3d o = v.pose.to_camera(Eigen::Vector3d::Zero());
    CHECK(o.z() == Approx(4.03).epsilon(0.02));
    CHECK(std::abs(o.x()) < 0.1);
    CHECK(std::abs(o.y()) < 0.1);
  }

  GSLIFT_REQUIRE_SHARED_DATA("instant_ngp_fox");
  const Capture fox = load_capture(test::shared_data("instant_ngp_fox"), {8, false, 8, false});
  REQUIRE(fox.views.size() == 50);
  CHECK(fox.test_views().size() == 7);
  CHECK(fox.views[0].camera.distortion.size() == 4);
  CHECK(fox.views[0].camera.width == 135);
  CHECK(fox.views[0].rgb.load().size() == cv::Size(135, 240));
}

TEST_CASE("Replica RGB-D: depth in metres and poses consistent across frames") {
  GSLIFT_REQUIRE_SHARED_DATA("replica_nice_slam_rgbd");
  const Capture c = load_capture(test::shared_data("replica_nice_slam_rgbd/room0"));
  REQUIRE(c.views.size() == 20);
  CHECK(c.views[0].name == "frame000000");
  check_depth_range(c.views[0], 0.1f, 10.f);
  CHECK(median_reprojection_depth_error(c.views[0], c.views[5]) < 0.02);
  const Capture office = load_capture(test::shared_data("replica_nice_slam_rgbd/office0"));
  CHECK(office.views.size() == 4);
}

TEST_CASE("3DMatch RGB-D: depth in metres and poses consistent across frames") {
  GSLIFT_REQUIRE_SHARED_DATA("threedmatch_seq01_rgbd");
  const Capture c = load_capture(test::shared_data("threedmatch_seq01_rgbd"));
  REQUIRE(c.views.size() == 5);
  CHECK(c.views[0].name == "seq-01_frame-000000");
  CHECK(c.views[0].camera.width == 640);
  CHECK(c.views[0].camera.fx == Approx(570.342205));
  check_depth_range(c.views[0], 0.2f, 10.f);
  CHECK(median_reprojection_depth_error(c.views[0], c.views[2]) < 0.05);
}

TEST_CASE("a views param names the training, the held-out or all views of a capture", "[capture]") {
  Capture capture;
  capture.views.resize(4);
  capture.views[2].held_out = true;
  CHECK(capture.views_named(ViewSet::Train) == std::vector<int>{0, 1, 3});
  CHECK(capture.views_named(ViewSet::Test) == std::vector<int>{2});
  CHECK(capture.views_named(ViewSet::All) == std::vector<int>{0, 1, 2, 3});
}
