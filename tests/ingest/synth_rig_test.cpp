// The OR rig reader against exact ground truth: a rig recording written by nodes/synth (colour
// through a rational distortion, depth from a camera of its own resolution and viewpoint) reads
// back as a capture whose registered depth matches the colour view's exact depth.
#include <algorithm>

#include "nodes/ingest/capture_annotations.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/synth/bvh.hpp"
#include "nodes/synth/drapes.hpp"
#include "nodes/synth/or_rig_capture.hpp"
#include "nodes/synth/render_view.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

TEST_CASE("a generated rig time step reads back; its depth registers within 1% of the truth") {
  const auto dir = test::scratch_dir("synth_rig") / "recording";
  // Exact depth (no simulated noise or holes): what is measured is the registration.
  const auto settings = synth::make_settings({{"seed", "0"},
                                              {"views", "4"},
                                              {"width", "320"},
                                              {"height", "240"},
                                              {"depth_noise", "0"},
                                              {"depth_holes", "0"}});
  synth::write_or_rig_recording(settings, dir, 2);
  for (const char* f :
       {"camera01.json", "camera04.json", "000000/colorimage", "000001/capture.yaml"})
    CHECK(fs::exists(dir / f));

  const Capture c = load_capture(dir / "000000");
  REQUIRE(c.views.size() == 4);
  CHECK(c.views[0].name == "camera01");
  CHECK_FALSE(c.test_views().empty());
  CHECK_FALSE(c.classes.empty());

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
    // Undistorted and cropped: a pinhole a little smaller than the captured image.
    CHECK(v.camera.distortion.empty());
    CHECK(v.camera.width < 320);
    CHECK(v.camera.width > 300);
    CHECK(v.rgb.load().size() == cv::Size(v.camera.width, v.camera.height));
    CHECK(v.gt_instance.load().size() == cv::Size(v.camera.width, v.camera.height));
    // The exact depth of the loaded view, rendered at its camera and true pose.
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
  double mean = 0;
  for (double e : errors) mean += e;
  mean /= errors.size();
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  WARN("rig registration: covered " << 100.0 * covered / seen << "% of the colour pixels, mean "
                                    << 100 * mean << "%, median " << 100 * errors[errors.size() / 2]
                                    << "%, within 1%: " << 100.0 * within / covered << "%");
  CHECK(double(covered) / seen > 0.9);
  CHECK(mean < 0.01);
  CHECK(double(within) / covered > 0.97);

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
