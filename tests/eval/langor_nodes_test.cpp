// inference.text_query -> eval.langor as graph nodes on a scene whose ground truth is known: the
// two-blob model with its instances, and a capture whose held-out view's semantic map is each
// blob's own alpha >= 0.5. Correct semantics score 100 everywhere; swapped semantics score 0.
#include <opencv2/core.hpp>

#include "nodes/eval/register.hpp"
#include "nodes/inference/register.hpp"
#include "nodes/inference/text_query.hpp"
#include "nodes/splat/ply_io.hpp"
#include "nodes/text/hashing_text_encoder.hpp"
#include "nodes/text/register.hpp"
#include "runtime/executor.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A source node "test.scene" emitting the two-blob model, its instances labelled `labels` and a
// capture with one training and one held-out view of it.
void register_scene(Registry& reg, std::vector<std::string> labels) {
  NodeSpec spec{"test.scene",
                "two blobs",
                {},
                {{"model", "GaussianModel", ""},
                 {"instances", "InstanceSet", ""},
                 {"capture", "Capture", ""}},
                {}};
  reg.add(std::move(spec), [labels](NodeContext& ctx) {
    const GaussianModel model = test::two_blobs();
    const HashingTextEncoder enc;  // text.encoder's default
    InstanceSet inst;
    inst.prototypes = Eigen::MatrixXf::Identity(2, 2);
    inst.labels = labels;
    inst.semantics.resize(2, enc.dim());
    for (int k = 0; k < 2; ++k) inst.semantics.row(k) = enc.encode(labels[k]).transpose();
    Capture cap;
    cap.name = "blobs";
    cap.classes = {{0, "background"}, {1, "patient"}, {2, "monitor"}};
    const QueryView qv(model, test::query_camera(), Pose{});
    cv::Mat1i semantic = cv::Mat1i::zeros(48, 64);
    semantic.setTo(1, qv.mask({1.f, 0.f}, 0.5f));
    semantic.setTo(2, qv.mask({0.f, 1.f}, 0.5f));
    for (int i = 0; i < 2; ++i) {
      View v;
      v.name = "cam_0" + std::to_string(i);
      v.camera = test::query_camera();
      v.held_out = i == 1;
      v.rgb = ImageSource::in_memory(cv::Mat(48, 64, CV_8UC3, cv::Scalar(40, 80, 120)));
      v.gt_semantic = ImageSource::in_memory(semantic);
      cap.views.push_back(v);
    }
    ctx.output("model", model);
    ctx.output("instances", inst);
    ctx.output("capture", cap);
  });
}

const char* kGraph = R"(graph: t
nodes:
  scene: {type: test.scene}
  text: {type: text.encoder}
  query:
    type: inference.text_query
    in: {model: scene.model, instances: scene.instances, encoder: text.encoder, capture: scene.capture}
  eval: {type: eval.langor, in: {predictions: query.predictions, capture: scene.capture}, params: {min_gt_pixels: 10}}
)";

double metric(const RunResult& r, const std::string& key) {
  return std::get<double>(r.node("eval")->records.at(key));
}

RunResult run_with(std::vector<std::string> labels, const std::filesystem::path& out = {}) {
  Registry reg;
  register_text_nodes(reg);
  register_inference_nodes(reg);
  register_eval_nodes(reg);
  register_scene(reg, std::move(labels));
  RunOptions o;
  o.out_dir = out;
  return run_graph_text(kGraph, reg, o);
}

}  // namespace

TEST_CASE("text query and eval nodes score a perfectly segmented scene 100") {
  const auto out = test::scratch_dir("langor_nodes");
  const RunResult r = run_with({"patient", "monitor"}, out);
  REQUIRE(r.ok());
  CHECK(metric(r, "queries") == 2);  // one held-out view, two classes present
  CHECK(metric(r, "mIoU") == Approx(100));
  CHECK(metric(r, "mLocAcc") == Approx(100));
  CHECK(metric(r, "mLocAcc_box") == Approx(100));
  CHECK(metric(r, "mAcc") == Approx(100));
  const auto pred = r.values.at("query.predictions").get<TextQueryResults>();
  REQUIRE(pred->views.size() == 1);  // views: test
  CHECK(pred->views[0].view == "cam_01");
  CHECK(pred->instances == std::vector<std::vector<int>>{{0}, {1}});
  const GaussianModel seg = read_ply(out / "query/segmented.ply");
  CHECK(seg.instance_ids == std::vector<int32_t>{0, 1});
  CHECK(seg.class_ids == std::vector<int32_t>{1, 2});
  for (const char* f : {"query/cam_01__patient_mask.png", "query/cam_01__monitor_relevancy.png",
                        "query/cam_01__monitor_overlay.png", "query/segmented.ply",
                        "query/queries.json", "eval/metrics.csv", "eval/metrics.md"})
    CHECK(std::filesystem::exists(out / f));
}

TEST_CASE("swapped instance semantics score 0") {
  const RunResult r = run_with({"monitor", "patient"});
  REQUIRE(r.ok());
  CHECK(metric(r, "mIoU") == Approx(0));
  CHECK(metric(r, "mLocAcc") == Approx(0));
  CHECK(metric(r, "mAcc") == Approx(0));
}
