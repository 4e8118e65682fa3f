// The OR rig reader against exact ground truth: a rig recording written by nodes/synth (colour
// through a rational distortion, depth from a camera of its own resolution and viewpoint) reads
// back as a capture whose registered depth matches the colour view's exact depth.
#include <algorithm>
#include <fstream>

#include "nodes/ingest/capture_annotations.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/synth/bvh.hpp"
#include "nodes/synth/drapes.hpp"
#include "nodes/synth/or_rig_capture.hpp"
#include "nodes/synth/render_view.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

// Every loaded view's registered depth against the exact depth of the loaded (undistorted,
// cropped) camera at its true pose: the share of colour pixels covered, the mean and median
// relative error, the share within 1%.
struct RigDepthError {
  double covered = 0, mean = 0, median = 0, within_1pc = 0;
};

RigDepthError rig_depth_error(const Capture& c, const synth::OrCaptureSettings& settings) {
  synth::OrScene scene = synth::make_or_scene(settings.scene);
  synth::drape_equipment(scene, settings.knobs.drapes, settings.scene.seed);
  const synth::Bvh bvh(scene.primitives);
  synth::RenderOptions plain;
  plain.shadows = false;
  long covered = 0, seen = 0, within = 0;
  std::vector<double> errors;
  for (size_t i = 0; i < c.views.size(); ++i) {
    const View& v = c.views[i];
    INFO(v.name);
    const cv::Mat exact =
        synth::render_view(scene, bvh, v.camera, scene.cameras[i].pose, plain).depth;
    const cv::Mat reg = v.depth.load();
    REQUIRE(reg.size() == exact.size());
    for (int y = 0; y < reg.rows; ++y)
      for (int x = 0; x < reg.cols; ++x) {
        const float truth = exact.at<float>(y, x), d = reg.at<float>(y, x);
        if (truth <= 0) continue;
        ++seen;
        if (d <= 0) continue;
        ++covered;
        const double e = std::abs(d - truth) / truth;
        errors.push_back(e);
        within += e <= 0.01;
      }
  }
  REQUIRE(covered > 0);
  RigDepthError r;
  for (double e : errors) r.mean += e;
  r.mean /= errors.size();
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  r.median = errors[errors.size() / 2];
  r.covered = double(covered) / seen;
  r.within_1pc = double(within) / covered;
  WARN("rig registration: covered " << 100 * r.covered << "% of the colour pixels, mean "
                                    << 100 * r.mean << "%, median " << 100 * r.median
                                    << "%, within 1%: " << 100 * r.within_1pc << "%");
  return r;
}

// Exact depth (no simulated noise or holes): what is measured is the registration.
synth::OrCaptureSettings exact_depth_rig() {
  return synth::make_settings({{"seed", "0"},
                               {"views", "4"},
                               {"width", "320"},
                               {"height", "240"},
                               {"depth_noise", "0"},
                               {"depth_holes", "0"}});
}

}  // namespace

TEST_CASE("a generated rig time step reads back, its depth registers within 1% of the truth") {
  const auto dir = test::scratch_dir("synth_rig") / "recording";
  const auto settings = exact_depth_rig();
  synth::write_or_rig_recording(settings, dir, 2);
  for (const char* f :
       {"camera01.json", "camera04.json", "000000/colorimage", "000001/capture.yaml"})
    CHECK(fs::exists(dir / f));

  const Capture c = load_capture(dir / "000000");
  REQUIRE(c.views.size() == 4);
  CHECK(c.views[0].name == "camera01");
  CHECK_FALSE(c.test_views().empty());
  CHECK_FALSE(c.classes.empty());

  for (const View& v : c.views) {
    INFO(v.name);
    // Undistorted and cropped: a pinhole a little smaller than the captured image.
    CHECK(v.camera.distortion.empty());
    CHECK(v.camera.width < 320);
    CHECK(v.camera.width > 300);
    CHECK(v.rgb.load().size() == cv::Size(v.camera.width, v.camera.height));
    CHECK(v.gt_instance.load().size() == cv::Size(v.camera.width, v.camera.height));
  }
  const RigDepthError e = rig_depth_error(c, settings);
  CHECK(e.covered > 0.9);
  CHECK(e.mean < 0.01);
  CHECK(e.within_1pc > 0.97);

  // The annotations are in the grid of the loaded images.
  const BoxSet boxes = load_vlm_boxes(c);
  size_t box_count = 0;
  for (const ViewBoxes& vb : boxes.views) box_count += vb.boxes.size();
  CHECK(box_count > 0);
  const MaskSet masks = load_sam_box_masks(c, boxes);
  for (size_t i = 0; i < masks.views.size(); ++i)
    for (const Mask& m : masks.views[i].masks)
      CHECK(m.pixels.size() == cv::Size(c.views[i].camera.width, c.views[i].camera.height));
}

TEST_CASE("MM-OR's pre-registered depth: read without registration, equal to the colour depth") {
  const auto dir = test::scratch_dir("synth_rig_registered") / "recording";
  const auto settings = exact_depth_rig();
  synth::write_or_rig_recording(settings, dir, 1, synth::RigDepth::registered);
  // No depth camera in the calibration; depth frames in the colour grid at half its size.
  std::ifstream calibration(dir / "camera01.json");
  const std::string text((std::istreambuf_iterator<char>(calibration)),
                         std::istreambuf_iterator<char>());
  CHECK(text.find("depth_parameters") == std::string::npos);
  CHECK(
      read_depth(dir / "000000" / "depthimage" / "camera01_depthimage-000000.tiff", 1000).size() ==
      cv::Size(160, 120));

  const Capture c = load_capture(dir / "000000");
  REQUIRE(c.views.size() == 4);
  const RigDepthError e = rig_depth_error(c, settings);
  CHECK(e.covered > 0.9);
  CHECK(e.mean < 0.01);
  CHECK(e.within_1pc > 0.97);
}
