// Selections rendered as masks, and exported as PLYs that reload with the same Gaussians.
#include "nodes/inference/selection_output.hpp"

#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "nodes/splat/ply_io.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("selection masks and PLY exports") {
  GaussianModel model = test::two_blobs();  // instance_ids {0, 1}: left, right
  model.instance_ids = {-1, 0};             // one selection: the right blob
  Capture capture;
  View v;
  v.name = "v0";
  v.camera = test::query_camera();
  capture.views.push_back(v);
  const MaskSet masks = render_selection_masks(model, capture, {0}, {"Right Blob"});
  REQUIRE(masks.views.size() == 1);
  const cv::Mat1b& m = masks.views[0].masks[0].pixels;
  CHECK(masks.views[0].masks[0].label == "Right Blob");
  CHECK(m(24, 47) == 255);  // the right blob's centre
  CHECK(m(24, 17) == 0);    // the left blob's
  const auto dir = test::scratch_dir("selection_output");
  write_selection_files(masks, model, {"Right Blob"}, capture, dir);
  CHECK(cv::imread((dir / "v0__right_blob_mask.png").string(), cv::IMREAD_GRAYSCALE)
            .at<uint8_t>(24, 47) == 255);
  // The object alone: exactly the right blob's parameters.
  const GaussianModel object = read_ply(dir / "right_blob.ply");
  REQUIRE(object.size() == 1);
  CHECK(object.means == std::vector<float>(model.means.begin() + 3, model.means.begin() + 6));
  CHECK(object.log_scales ==
        std::vector<float>(model.log_scales.begin() + 3, model.log_scales.end()));
  CHECK(object.opacity_logits[0] == model.opacity_logits[1]);
  CHECK(object.instance_ids.empty());
  // The scene: every Gaussian, with the selection as instance_id.
  const GaussianModel scene = read_ply(dir / "scene_selection.ply");
  CHECK(scene.means == model.means);
  CHECK(scene.instance_ids == model.instance_ids);
}
