// lifting.cvp / lifting.mask_level and association.instance_mask_gaussian as graph nodes on a
// tiny rendered scene: two objects of nine Gaussians each in front of a large background
// Gaussian, seen by two training views and one held-out view. The masks are the objects'
// rendered footprints, so the right answer is known: two instances, "table" and "chair", every
// object Gaussian in its object's instance, the background unassigned.
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "nodes/association/register.hpp"
#include "nodes/lifting/register.hpp"
#include "nodes/scene/instances.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/training_feature_maps.hpp"
#include "nodes/text/register.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

constexpr int kObjectGaussians = 9;  // per object; Gaussians 0..8 table, 9..17 chair, 18 wall

GaussianModel two_objects_and_a_wall() {
  GaussianModel m;
  m.feature_dim = 4;
  m.resize(2 * kObjectGaussians + 1);
  for (int g = 0; g < static_cast<int>(m.size()); ++g) {
    const bool wall = g == 2 * kObjectGaussians;
    const int object = g / kObjectGaussians;  // 0 table, 1 chair, 2 wall
    const int i = g % 3 - 1, j = (g / 3) % 3 - 1;
    const Eigen::Vector3f mean =
        wall ? Eigen::Vector3f(0, 0, 8)
             : Eigen::Vector3f((object == 0 ? -0.6f : 0.6f) + 0.1f * i, 0.1f * j, 4);
    const Eigen::Vector3f scale =
        wall ? Eigen::Vector3f(4, 4, 0.05f) : Eigen::Vector3f::Constant(0.12f);
    for (int k = 0; k < 3; ++k) {
      m.means[g * 3 + k] = mean[k];
      m.log_scales[g * 3 + k] = std::log(scale[k]);
    }
    m.opacity_logits[g] = wall ? 1.f : 4.f;
    m.features[g * 4 + object] = 1.f;
  }
  return m;
}

// Pixels where `object` explains most of the rendered feature (F . e_object > 0.9).
Mask footprint(const RenderOutput& r, int object, const std::string& label) {
  Mask mask;
  mask.pixels = cv::Mat1b::zeros(r.height, r.width);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      const float* f = r.features.data() + (y * r.width + x) * r.feature_dim;
      if (f[object] > 0.9f) mask.pixels(y, x) = 255;
    }
  mask.label = label;
  return mask;
}

struct TinyScene {
  Capture capture;
  GaussianModel model;
  MaskSet masks;
};

TinyScene tiny_scene() {
  TinyScene s;
  s.model = two_objects_and_a_wall();
  s.capture.name = "tiny";
  const double shifts[3] = {0.0, 0.2, -0.2};
  RenderSettings settings;
  settings.rgb = false;
  settings.features = true;
  for (int v = 0; v < 3; ++v) {
    View view;
    view.name = "cam_" + std::to_string(v);
    view.camera = Camera{40, 30, 40, 40, 20, 15, {}};
    view.pose.t = Eigen::Vector3d(shifts[v], 0, 0);
    view.held_out = v == 2;
    const RenderOutput r = render(s.model, view.camera, view.pose, settings);
    s.masks.views.push_back({view.name, {footprint(r, 0, "table"), footprint(r, 1, "chair")}});
    s.capture.views.push_back(std::move(view));
  }
  return s;
}

Registry registry_with_scene() {
  Registry reg;
  register_lifting_nodes(reg);
  register_association_nodes(reg);
  register_text_nodes(reg);
  reg.add(
      NodeSpec{
          "test.tiny_scene",
          "the tiny two-object scene",
          {},
          {{"capture", "Capture", ""}, {"model", "GaussianModel", ""}, {"masks", "MaskSet", ""}},
          {}},
      [](NodeContext& ctx) {
        TinyScene s = tiny_scene();
        ctx.output("capture", std::move(s.capture));
        ctx.output("model", std::move(s.model));
        ctx.output("masks", std::move(s.masks));
      });
  return reg;
}

std::string graph(const std::string& lift) {
  return "graph: t\n"
         "nodes:\n"
         "  scene: {type: test.tiny_scene}\n"
         "  words: {type: text.encoder, params: {dim: 64}}\n"
         "  lift: " +
         lift +
         "\n"
         "  assoc:\n"
         "    type: association.instance_mask_gaussian\n"
         "    in: {model: scene.model, capture: scene.capture, masks: scene.masks,\n"
         "         instances: lift.instances, encoder: words.encoder}\n";
}

const std::string kLiftInputs =
    "in: {model: scene.model, capture: scene.capture, masks: scene.masks}";

// The expected association: objects' Gaussians in one instance each, labelled by their masks.
void check_association(const RunResult& run) {
  REQUIRE(run.ok());
  const auto set = run.values.at("assoc.instances").get<InstanceSet>();
  const auto model = run.values.at("assoc.model").get<GaussianModel>();
  REQUIRE(set->size() == 2);
  REQUIRE(model->instance_ids.size() == model->size());
  const int table = model->instance_ids[0], chair = model->instance_ids[kObjectGaussians];
  REQUIRE(table >= 0);
  REQUIRE(chair >= 0);
  CHECK(table != chair);
  CHECK(set->labels[table] == "table");
  CHECK(set->labels[chair] == "chair");
  for (int g = 0; g < kObjectGaussians; ++g) {
    CHECK(model->instance_ids[g] == table);
    CHECK(model->instance_ids[kObjectGaussians + g] == chair);
  }
  CHECK(model->instance_ids[2 * kObjectGaussians] == -1);  // the wall: no mask, dissimilar
  // Training views' masks matched; the held-out view's left alone.
  CHECK(set->mask_instance ==
        std::vector<std::vector<int>>{{table, chair}, {table, chair}, {-1, -1}});
  CHECK(std::get<double>(run.node("assoc")->records.at("matched_masks")) == 4);
}

}  // namespace

TEST_CASE("lifting.cvp then association on a tiny rendered scene") {
  const Registry reg = registry_with_scene();
  RunOptions options;
  options.out_dir = test::scratch_dir("association_node");
  const RunResult run = run_graph_text(
      graph("{type: lifting.cvp, " + kLiftInputs + ", params: {samples_per_mask: 60}}"), reg,
      options);
  check_association(run);
  const auto& lift = run.node("lift")->records;
  CHECK(std::get<double>(lift.at("instances")) == 2);
  CHECK(std::get<double>(lift.at("training_views")) == 2);
  CHECK(std::get<double>(lift.at("noise_fraction")) < 0.2);

  std::ifstream file(options.out_dir / "assoc" / "instances.json");
  REQUIRE(file);
  const nlohmann::json instances = nlohmann::json::parse(file);
  REQUIRE(instances.size() == 2);
  for (const auto& entry : instances) {
    const std::string label = entry.at("label");
    CHECK(entry.at("mask_labels") == std::vector<std::string>{label, label});
    CHECK(entry.at("gaussians") == kObjectGaussians);
  }
}

TEST_CASE("lifting.mask_level is a one-line swap with the same answer here") {
  const RunResult run = run_graph_text(graph("{type: lifting.mask_level, " + kLiftInputs + "}"),
                                       registry_with_scene());
  check_association(run);
  CHECK(std::get<double>(run.node("lift")->records.at("samples")) == 4);  // one per training mask
}

TEST_CASE("feature maps: bad masks are bad input") {
  TinyScene s = tiny_scene();
  SECTION("a view the capture does not have") {
    s.masks.views[0].view = "cam_9";
    CHECK_THROWS_AS(render_training_feature_maps(s.model, s.capture, s.masks, false), InputError);
  }
  SECTION("a mask of the wrong size") {
    s.masks.views[1].masks[0].pixels = cv::Mat1b::zeros(10, 10);
    CHECK_THROWS_AS(render_training_feature_maps(s.model, s.capture, s.masks, false), InputError);
  }
  SECTION("only held-out views have masks") {
    s.masks.views.erase(s.masks.views.begin(), s.masks.views.begin() + 2);
    CHECK_THROWS_AS(render_training_feature_maps(s.model, s.capture, s.masks, false), InputError);
  }
  SECTION("a model without features") {
    s.model.feature_dim = 0;
    s.model.features.clear();
    CHECK_THROWS_AS(render_training_feature_maps(s.model, s.capture, s.masks, false), InputError);
  }
}

TEST_CASE("feature maps: training views only, contribution = blend weights summed") {
  const TinyScene s = tiny_scene();
  const TrainingFeatureMaps t = render_training_feature_maps(s.model, s.capture, s.masks, true);
  CHECK(t.mask_views == std::vector<int>{0, 1});
  CHECK(t.capture_views == std::vector<int>{0, 1});
  REQUIRE(t.maps.size() == 2);
  REQUIRE(t.contribution.size() == s.model.size());
  // Sum over Gaussians of their contributions = sum over pixels of the accumulated alpha.
  RenderSettings alpha_only;
  alpha_only.rgb = false;
  alpha_only.alpha = true;
  double alpha_sum = 0;
  for (const int v : t.capture_views) {
    const View& view = s.capture.views[v];
    for (const float a : render(s.model, view.camera, view.pose, alpha_only).alpha) alpha_sum += a;
  }
  double contribution_sum = 0;
  for (const float c : t.contribution) contribution_sum += c;
  CHECK(contribution_sum == Approx(alpha_sum).epsilon(1e-4));
  // The feature maps are the rendered features: the chair channel at the chair's centre pixel.
  const float* centre = t.maps[0].at(26, 15);
  CHECK(centre[1] > 0.9f);
  CHECK(centre[0] == Approx(0).margin(1e-3));
}

// The empty-result checks (runtime/empty_result.hpp): an empty lifting or association fails its
// node as bad input (gslift run's exit 4) with the cause, nothing downstream runs, and
// allow_empty: true accepts the empty output.
TEST_CASE("a lifting with no instance fails its node, allow_empty accepts it") {
  // Four training masks, one sample each: HDBSCAN with min_cluster_size 5 calls all of them noise.
  const std::string lift =
      "{type: lifting.mask_level, " + kLiftInputs + ", params: {min_cluster_size: 5";
  const RunResult empty = run_graph_text(graph(lift + "}}"), registry_with_scene());
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error->kind == RunError::Kind::BadInput);
  CHECK(empty.error->node == "lift");
  CHECK_THAT(empty.error->message,
             Catch::Matchers::Contains("lifting.mask_level: no instance lifted from 4 samples of "
                                       "2 training views") &&
                 Catch::Matchers::Contains("allow_empty: true"));
  CHECK(empty.node("assoc")->status == NodeStatus::Pending);

  // Accepted, the empty lifting reaches the association, which has nothing to associate.
  const RunResult allowed =
      run_graph_text(graph(lift + ", allow_empty: true}}"), registry_with_scene());
  CHECK(allowed.node("lift")->status == NodeStatus::Ok);
  CHECK(std::get<double>(allowed.node("lift")->records.at("instances")) == 0);
  REQUIRE_FALSE(allowed.ok());
  CHECK(allowed.error->node == "assoc");
  CHECK_THAT(allowed.error->message,
             Catch::Matchers::Contains("association.instance_mask_gaussian: no instance to "
                                       "associate (the lifting found none)"));
}

TEST_CASE(
    "an association with no Gaussian in any instance fails its node, allow_empty accepts it") {
  // Every Gaussian's summed blend weight is far below this: none may join an instance.
  const std::string g = graph("{type: lifting.mask_level, " + kLiftInputs + "}") +
                        "    params: {min_contribution: 1.0e9";
  const RunResult empty = run_graph_text(g + "}\n", registry_with_scene());
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error->kind == RunError::Kind::BadInput);
  CHECK(empty.error->node == "assoc");
  CHECK_THAT(empty.error->message,
             Catch::Matchers::Contains("association.instance_mask_gaussian: no Gaussian joined "
                                       "any of the 2 instances (min_similarity, "
                                       "min_contribution)") &&
                 Catch::Matchers::Contains("allow_empty: true"));
  CHECK_FALSE(empty.values.count("assoc.model"));

  const RunResult allowed = run_graph_text(g + ", allow_empty: true}\n", registry_with_scene());
  REQUIRE(allowed.ok());
  const auto model = allowed.values.at("assoc.model").get<GaussianModel>();
  for (const int32_t k : model->instance_ids) CHECK(k == -1);
}
