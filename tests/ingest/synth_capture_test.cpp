// The contract between nodes/synth (writer) and nodes/ingest (reader): a generated OR capture
// reads back through every ingest path with consistent numbers.
#include <fstream>

#include "nodes/ingest/capture_annotations.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/synth/or_capture.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("a synthetic OR capture reads back through capture, VLM and SAM loaders") {
  const auto dir = test::scratch_dir("synth_roundtrip") / "capture";
  const auto settings =
      synth::make_settings({{"seed", "1"}, {"views", "4"}, {"width", "96"}, {"height", "72"}});
  synth::write_or_capture(settings, dir);

  const Capture c = load_capture(dir);
  CHECK(c.name == synth::capture_name(settings));
  REQUIRE(c.views.size() == 4);
  CHECK_FALSE(c.test_views().empty());
  CHECK_FALSE(c.train_views().empty());
  CHECK_FALSE(c.classes.empty());
  for (const View& v : c.views) {
    INFO(v.name);
    CHECK(v.camera.width == 96);
    CHECK(v.camera.distortion.empty());
    CHECK(v.rgb.load().size() == cv::Size(96, 72));
    const cv::Mat gt_depth = v.gt_depth.load(), prior = v.depth.load();
    REQUIRE(gt_depth.type() == CV_32FC1);
    REQUIRE(prior.type() == CV_32FC1);
    // The prior is the exact depth plus simulated noise: close in the median, in metres.
    std::vector<float> rel;
    for (int y = 0; y < 72; ++y)
      for (int x = 0; x < 96; ++x)
        if (gt_depth.at<float>(y, x) > 0 && prior.at<float>(y, x) > 0)
          rel.push_back(std::abs(prior.at<float>(y, x) / gt_depth.at<float>(y, x) - 1));
    REQUIRE(rel.size() > 1000);
    std::nth_element(rel.begin(), rel.begin() + rel.size() / 2, rel.end());
    CHECK(rel[rel.size() / 2] < 0.1);
    // Every instance id of the ground truth has a class.
    const cv::Mat ids = v.gt_instance.load();
    REQUIRE(ids.type() == CV_32SC1);
    for (int y = 0; y < 72; y += 4)
      for (int x = 0; x < 96; x += 4) {
        const int id = ids.at<int>(y, x);
        if (id != 0) CHECK(c.instance_class.count(id) == 1);
      }
    const cv::Mat normals = v.gt_normal.load();
    REQUIRE(normals.type() == CV_32FC3);
    const cv::Vec3f n = normals.at<cv::Vec3f>(36, 48);
    if (gt_depth.at<float>(36, 48) > 0) CHECK(cv::norm(n) == Approx(1).margin(1e-3));
  }

  const BoxSet boxes = load_vlm_boxes(c);
  REQUIRE(boxes.views.size() == 4);
  size_t box_count = 0;
  for (const ViewBoxes& vb : boxes.views) {
    CHECK(vb.rounds > 0);
    for (const Box& b : vb.boxes) {
      CHECK(b.x1 >= 0);
      CHECK(b.x2 <= 96);
      CHECK(b.area() > 0);
      CHECK(b.round < vb.rounds);
    }
    box_count += vb.boxes.size();
  }
  CHECK(box_count > 0);

  const MaskSet masks = load_sam_box_masks(c, boxes);
  size_t mask_count = 0;
  for (size_t v = 0; v < masks.views.size(); ++v)
    for (const Mask& m : masks.views[v].masks) {
      REQUIRE(m.box_index >= 0);
      REQUIRE(m.box_index < static_cast<int>(boxes.views[v].boxes.size()));
      CHECK(m.label == boxes.views[v].boxes[m.box_index].label);
      CHECK(m.pixels.size() == cv::Size(96, 72));
      ++mask_count;
    }
  CHECK(mask_count > 0);

  const MaskSet autos = load_sam_auto_masks(c);
  size_t auto_count = 0;
  for (const ViewMasks& vm : autos.views) auto_count += vm.masks.size();
  CHECK(auto_count > 0);
}
