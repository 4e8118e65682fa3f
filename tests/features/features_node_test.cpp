// boxes.to_masks and features.contrastive as graph nodes, wired as in the LangOR graph on a small
// embedded OR capture: VLM boxes -> clusters -> masks, reconstruction -> contrastive features.
#include <cstdlib>

#include "nodes/boxes/register.hpp"
#include "nodes/features/register.hpp"
#include "nodes/ingest/register.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/splat/register.hpp"
#include "nodes/synth/register.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("boxes.to_masks and features.contrastive nodes on a small embedded capture",
          "[features]") {
  ::setenv("GSLIFT_CACHE", test::scratch_dir("features_node_cache").c_str(), 1);
  Registry registry;
  register_ingest_nodes(registry);
  register_synth_nodes(registry);
  register_splat_nodes(registry);
  register_boxes_nodes(registry);
  register_features_nodes(registry);
  const RunResult r = run_graph_text(R"(
graph: features
nodes:
  cap: {type: ingest.capture, params: {path: "embedded:or?seed=1&views=4&width=128&height=96"}}
  vlm: {type: ingest.vlm, in: {capture: cap.capture}}
  cluster: {type: boxes.cluster, in: {boxes: vlm.boxes}}
  sam: {type: ingest.sam_masks, in: {capture: cap.capture, boxes: cluster.clusters}, params: {kind: box}}
  masks: {type: boxes.to_masks, in: {clusters: cluster.clusters, capture: cap.capture, sam: sam.masks}}
  splat: {type: splat.reconstruct, in: {capture: cap.capture},
          params: {iterations: 20, min_train_psnr: 0}}  # a model to train on, not judged
  features: {type: features.contrastive,
             in: {model: splat.model, capture: cap.capture, masks: masks.masks},
             params: {iterations: 40, dim: 8, pixels_per_iteration: 64}}
)",
                                     registry);
  ::unsetenv("GSLIFT_CACHE");
  INFO((r.error ? r.error->str() : std::string()));
  REQUIRE(r.ok());

  const auto clusters = r.values.at("cluster.clusters").get<BoxSet>();
  const auto masks = r.values.at("masks.masks").get<MaskSet>();
  REQUIRE(masks->views.size() == clusters->views.size());
  size_t boxes = 0, train_masks = 0;
  const auto capture = r.values.at("cap.capture").get<Capture>();
  for (size_t v = 0; v < masks->views.size(); ++v) {
    REQUIRE(masks->views[v].masks.size() == clusters->views[v].boxes.size());
    boxes += clusters->views[v].boxes.size();
    if (!capture->views[capture->find_view(masks->views[v].view)].held_out)
      for (const Mask& m : masks->views[v].masks) train_masks += cv::countNonZero(m.pixels) > 0;
  }
  // The embedded capture ships a SAM mask for every VLM box.
  CHECK(std::get<double>(r.node("masks")->records.at("from_sam")) == double(boxes));

  const auto before = r.values.at("splat.model").get<GaussianModel>();
  const auto after = r.values.at("features.model").get<GaussianModel>();
  CHECK(after->feature_dim == 8);
  CHECK(after->features.size() == before->size() * 8);
  CHECK(after->means == before->means);
  const auto& rec = r.node("features")->records;
  CHECK(std::get<double>(rec.at("masks")) == double(train_masks));
  CHECK(std::get<double>(rec.at("loss_end")) < std::get<double>(rec.at("loss_start")));
}
