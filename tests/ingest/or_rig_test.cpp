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

TEST_CASE("a rig time step is a capture, depth at its own size registers to colour") {
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

namespace {

// tests/data/ingest/k4a_rig: a hand-written Azure Kinect raw calibration; its README has the
// numbers each mode gives.
const fs::path kK4aRig = fs::path(GSLIFT_TEST_DATA) / "ingest" / "k4a_rig";

}  // namespace

TEST_CASE("Azure Kinect raw calibration: modes scale the normalised intrinsics, p2 before p1") {
  const fs::path file = kK4aRig / "camera01.json";
  const OrRigCamera c = read_or_rig_k4a_camera(file, {1280, 720}, cv::Size(320, 288));
  // 720P: the 4096 x 3072 calibration at 1280 x 960, 120 rows cropped off the top; gslift's pixel
  // corner at 0 is the raw file's convention (the SDK subtracts 0.5 for OpenCV's).
  CHECK(c.colour.width == 1280);
  CHECK(c.colour.height == 720);
  CHECK(c.colour.fx == 640);          // 0.5 * 1280
  CHECK(c.colour.fy == Approx(648));  // 0.675 * 960
  CHECK(c.colour.cx == 645);          // 0.50390625 * 1280
  CHECK(c.colour.cy == Approx(348));  // 0.4875 * 960 - 120
  // Stored k1..k6 codx cody p2 p1; OpenCV's k1 k2 p1 p2 k3 k4 k5 k6.
  CHECK(c.colour.distortion ==
        std::vector<double>{0.1, 0.02, 0.0001, 0.0002, 0.003, 0.4, 0.05, 0.006});
  // NFOV 2x2 binned: 1024 x 1024 binned to 512 x 512, cropped by (96, 90) to 320 x 288.
  REQUIRE(c.depth);
  CHECK(c.depth->width == 320);
  CHECK(c.depth->height == 288);
  CHECK(c.depth->fx == 256);
  CHECK(c.depth->fy == 256);
  CHECK(c.depth->cx == 164);  // 0.5078125 * 512 - 96
  CHECK(c.depth->cy == 166);  // 0.5 * 512 - 90
  CHECK(c.depth->distortion.empty());
  // Rt is world -> sensor with the depth camera as the world: depth -> colour is the colour Rt.
  CHECK((c.depth_to_colour.t - Eigen::Vector3d(-0.032, -0.002, 0.004)).norm() < 1e-12);
  CHECK(c.depth_to_colour.R(1, 2) == Approx(-0.10452846326765347));
  // camera01_pose.json puts the depth camera at (1, 2, 3) in OpenGL axes; the colour camera sits
  // at -R^T t = (0.032, 0.0015709, -0.0041871) in the depth camera's (OpenCV) frame, y and z
  // flipped into the world.
  CHECK((c.colour_pose.centre() - Eigen::Vector3d(1.032, 1.998429070062334, 3.0041871445080084))
            .norm() < 1e-9);

  // Other modes of the same file: 1536P (no crop), NFOV unbinned (crop 192, 180).
  const OrRigCamera m = read_or_rig_k4a_camera(file, {2048, 1536}, cv::Size(640, 576));
  CHECK(m.colour.fx == 1024);
  CHECK(m.colour.fy == Approx(1036.8));
  CHECK(m.colour.cx == 1032);
  CHECK(m.colour.cy == Approx(748.8));
  REQUIRE(m.depth);
  CHECK(m.depth->fx == 512);
  CHECK(m.depth->cx == 328);
  CHECK(m.depth->cy == 332);
  // Depth of no depth mode's size is depth registered to colour already: no depth camera.
  CHECK_FALSE(read_or_rig_k4a_camera(file, {2048, 1536}, cv::Size(1024, 768)).depth);
  CHECK_THROWS_WITH(read_or_rig_k4a_camera(file, {1000, 700}, std::nullopt),
                    Contains("not the size of an Azure Kinect colour mode"));
}

TEST_CASE(
    "Azure Kinect raw calibration: a time step registers depth through it, bad files are refused") {
  const auto rec = test::scratch_dir("k4a_rig_recording");
  fs::copy_file(kK4aRig / "camera01.json", rec / "camera01.json");
  fs::copy_file(kK4aRig / "camera01_pose.json", rec / "camera01_pose.json");
  const fs::path step = rec / "000000";
  write_rgb_png(step / "colorimage" / "camera01_colorimage-000000.png",
                cv::Mat(720, 1280, CV_8UC3, cv::Scalar::all(128)));
  // A wall 2 m in front of the depth camera.
  write_depth_png_mm(step / "depthimage" / "camera01_depthimage-000000.tiff",
                     cv::Mat(288, 320, CV_32FC1, cv::Scalar(2.0f)));
  CaptureOptions raw;
  raw.undistort = false;
  const Capture c = load_capture(step, raw);
  REQUIRE(c.views.size() == 1);
  CHECK(c.views[0].camera.fx == 640);
  const cv::Mat d = c.views[0].depth.load();
  REQUIRE(d.size() == cv::Size(1280, 720));
  // Along the colour camera's axis (no distortion there) the wall, tilted by 6 degrees and
  // offset, is at z_c with -s (0 - t_y) + c (z_c - t_z) = 2: z_c = (2 + 0.002 s) / c + 0.004.
  // Pixel (645, 348)'s centre is half a pixel off the axis: 0.16 mm on this slope.
  CHECK(d.at<float>(348, 645) == Approx(2.0152267675975644).epsilon(2e-4));

  // A second camera without a pose file: the rig cannot place it.
  fs::copy_file(kK4aRig / "camera01.json", rec / "camera02.json");
  write_rgb_png(step / "colorimage" / "camera02_colorimage-000000.png",
                cv::Mat(720, 1280, CV_8UC3, cv::Scalar::all(128)));
  CHECK_THROWS_WITH(load_capture(step, raw), Contains("camera02_pose.json"));
  fs::remove(rec / "camera02.json");
  fs::remove(step / "colorimage" / "camera02_colorimage-000000.png");

  // Translations in millimetres instead of the export's metres.
  std::ifstream in(kK4aRig / "camera01.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string metres = "[-0.032, -0.002, 0.004]";
  REQUIRE(text.find(metres) != std::string::npos);
  text.replace(text.find(metres), metres.size(), "[-32, -2, 4]");
  write_rig_text(rec / "camera01.json", text);
  CHECK_THROWS_WITH(load_capture(step, raw), Contains("in metres"));
  // p1 and p2 are the last two of 14; a Rational6KT model is refused.
  text.replace(text.find("[-32, -2, 4]"), 12, metres);
  const std::string model =
      "CALIBRATION_LensDistortionModelBrownConrady\"\n        },\n        \"Location\": "
      "\"CALIBRATION_CameraLocationPV0";
  REQUIRE(text.find(model) != std::string::npos);
  text.replace(text.find(model), 43, "CALIBRATION_LensDistortionModelRational6KT");
  write_rig_text(rec / "camera01.json", text);
  CHECK_THROWS_WITH(load_capture(step, raw), Contains("Rational6KT"));
}
