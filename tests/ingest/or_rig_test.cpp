#include "nodes/ingest/or_rig.hpp"

#include <fstream>

#include "nodes/ingest/capture_loader.hpp"
#include "nodes/scene/image_io.hpp"
#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

void write_rig_text(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// A camera0X.json as 4D-OR's loaders read it: fov_x/fov_y focal lengths, the intrinsics matrix
// transposed, radial k1..k6 and tangential p1 p2, the depth camera's pose and colour -> depth.
std::string hand_written_camera(const std::string& pose_translation) {
  return R"({"value0": {
  "color_parameters": {"width": 64, "height": 48, "fov_x": 50, "fov_y": 52, "c_x": 31.5, "c_y": 23.5,
    "intrinsics_matrix": {"m00": 50, "m10": 0, "m20": 31.5, "m01": 0, "m11": 52, "m21": 23.5,
                          "m02": 0, "m12": 0, "m22": 1},
    "radial_distortion": {"m00": 0.1, "m10": 0.2, "m20": 0.3, "m30": 0.4, "m40": 0.5, "m50": 0.6},
    "tangential_distortion": {"m00": 0.01, "m10": 0.02}},
  "depth_parameters": {"width": 32, "height": 24, "fov_x": 20, "fov_y": 20, "c_x": 15.5, "c_y": 11.5},
  "camera_pose": {"rotation": {"x": 0, "y": 0, "z": 0, "w": 1},
                  "translation": )" +
         pose_translation + R"(},
  "color2depth_transform": {"rotation": {"x": 0, "y": 0, "z": 0, "w": 1},
                            "translation": {"m00": 0.032, "m10": 0, "m20": 0}}}})";
}

}  // namespace

TEST_CASE("rig calibration: focal lengths, transposed K, OpenCV order, OpenGL axes") {
  const auto dir = test::scratch_dir("or_rig_calibration");
  write_rig_text(dir / "camera01.json", hand_written_camera(R"({"m00": 1, "m10": 2, "m20": 3})"));
  const OrRigCamera c = read_or_rig_camera(dir / "camera01.json");
  CHECK(c.colour.fx == 50);
  CHECK(c.colour.fy == 52);
  CHECK(c.colour.cx == 32);  // c_x in OpenCV's convention, pixel centres at integers
  CHECK(c.colour.cy == 24);
  CHECK(c.colour.distortion == std::vector<double>{0.1, 0.2, 0.01, 0.02, 0.3, 0.4, 0.5, 0.6});
  REQUIRE(c.depth);
  CHECK(c.depth->width == 32);
  CHECK(c.depth->distortion.empty());
  // Colour camera-to-world (OpenGL axes) = camera_pose * color2depth: centre at (1.032, 2, 3),
  // looking down -z of the world; in OpenCV axes a point 2 m in front of it is at z = +2.
  CHECK((c.colour_pose.centre() - Eigen::Vector3d(1.032, 2, 3)).norm() < 1e-12);
  const Eigen::Vector3d ahead = c.colour_pose.to_camera({1.032, 2.5, 1});
  CHECK((ahead - Eigen::Vector3d(0, -0.5, 2)).norm() < 1e-12);
  // Depth -> colour moves the depth camera's origin 3.2 cm along -x (colour sits at +x).
  CHECK((c.depth_to_colour.t - Eigen::Vector3d(-0.032, 0, 0)).norm() < 1e-12);

  // The writer's file reads back as the same camera.
  write_rig_text(dir / "camera02.json", or_rig_camera_json(c));
  const OrRigCamera back = read_or_rig_camera(dir / "camera02.json");
  CHECK(back.colour.distortion == c.colour.distortion);
  CHECK(back.colour.cx == c.colour.cx);
  CHECK((back.colour_pose.R - c.colour_pose.R).norm() < 1e-12);
  CHECK((back.colour_pose.t - c.colour_pose.t).norm() < 1e-12);
  CHECK((back.depth_to_colour.t - c.depth_to_colour.t).norm() < 1e-12);

  // A matrix that is not the transposed layout is an error naming the field.
  std::string bad = hand_written_camera(R"({"m00": 0, "m10": 0, "m20": 0})");
  bad.replace(bad.find("\"m20\": 31.5"), 11, "\"m20\": 0.0 ");
  bad.replace(bad.find("\"m02\": 0"), 8, "\"m02\": 31.5");
  write_rig_text(dir / "camera03.json", bad);
  CHECK_THROWS_WITH(read_or_rig_camera(dir / "camera03.json"),
                    Contains("intrinsics_matrix") && Contains("transposed"));
  fs::remove(dir / "camera03.json");
  write_rig_text(dir / "camera04.json", R"({"value0": {"color_parameters": {"width": 64}}})");
  CHECK_THROWS_WITH(read_or_rig_camera(dir / "camera04.json"),
                    Contains("camera04.json") && Contains("color_parameters.height"));
}

TEST_CASE("a rig time step is a capture; depth at its own size registers to colour") {
  const auto rec = test::scratch_dir("or_rig_recording");
  // Calibrations in the recording, frames in its time-step folder.
  write_rig_text(rec / "camera01.json", hand_written_camera(R"({"m00": 0, "m10": 0, "m20": 0})"));
  write_rig_text(rec / "camera02.json", hand_written_camera(R"({"m00": 1, "m10": 0, "m20": 0})"));
  const fs::path step = rec / "000007";
  for (const char* cam : {"camera01", "camera02"}) {
    write_rgb_png(step / "colorimage" / (std::string(cam) + "_colorimage-000007.png"),
                  cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(128)));
    write_depth_png_mm(step / "depthimage" / (std::string(cam) + "_depthimage-000007.tiff"),
                       cv::Mat(24, 32, CV_32FC1, cv::Scalar(2.0f)));
  }
  CaptureOptions raw;
  raw.undistort = false;
  const Capture c = load_capture(step, raw);
  REQUIRE(c.views.size() == 2);
  CHECK(c.views[0].name == "camera01");
  CHECK(c.views[1].name == "camera02");
  CHECK((c.views[1].pose.centre() - Eigen::Vector3d(1.032, 0, 0)).norm() < 1e-12);
  const cv::Mat d = c.views[0].depth.load();
  REQUIRE(d.size() == cv::Size(64, 48));  // the colour camera's size
  // The wall 2 m from the depth camera is 2 m from the colour camera (a sideways offset).
  CHECK(d.at<float>(24, 32) == Approx(2.0f));
  CHECK(cv::countNonZero(d) > 64 * 48 / 2);

  // Two time steps in one folder, and a frame of a camera without calibration, are errors.
  write_rgb_png(step / "colorimage" / "camera01_colorimage-000008.png",
                cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(128)));
  CHECK_THROWS_WITH(load_capture(step),
                    Contains("2 frames of camera01") && Contains("one time step"));
  fs::remove(step / "colorimage" / "camera01_colorimage-000008.png");
  write_rgb_png(step / "colorimage" / "camera03_colorimage-000007.png",
                cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(128)));
  CHECK_THROWS_WITH(load_capture(step), Contains("no calibration camera03.json"));
}
