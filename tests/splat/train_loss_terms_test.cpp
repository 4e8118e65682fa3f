// Each loss term reconstruct() trains over (loss_terms.hpp), on its own: its gradient with
// respect to the model, as the training loop assembles it (an Image term's image gradient through
// the rasterizer's backward pass, a Ray or Model term's own), against central differences of its
// value over hand-placed Gaussians before a pinhole; and the terms the options switch on.
#include <cmath>
#include <memory>

#include "nodes/splat/loss_terms.hpp"
#include "tests/splat/pinhole_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// The pinhole scene with targets: a random image, a prior that observes a wall at 4 m on the left
// (columns 0-19) and an object at 1.5 m on the right, and normals facing the camera.
struct TermScene : test::PinholeScene {
  TargetImages target;
  std::vector<DepthObservation> observations;
  GaussianModel model;

  TermScene() {
    target.camera = cam;
    cv::Mat rgb(cam.height, cam.width, CV_32FC3);
    cv::randu(rgb, 0.f, 1.f);
    target.rgb = rgb;
    target.ssim.emplace(target.rgb);
    cv::Mat1f depth(cam.height, cam.width, 4.f);
    depth(cv::Rect(20, 0, 20, 30)) = 1.5f;
    target.depth = depth;
    target.normals = cv::Mat(cam.height, cam.width, CV_32FC3, cv::Scalar(0.f, 0.f, -1.f));
    observations.push_back({&cam, &pose, depth});
    // Four Gaussians, each with three distinct scales (the rendered normal is the shortest axis:
    // no ties), in front of the wall, straddling the edge, on the object's near side at its
    // silhouette and on the wall.
    model.resize(4);
    place(model, 0, 10.3, 14.8, 2.0, 0.12, 0.6);
    place(model, 1, 19.6, 15.2, 3.0, 0.1, 0.5);
    place(model, 2, 20.4, 9.4, 1.5, 0.08, 0.7);
    place(model, 3, 29.5, 20.1, 3.9, 0.2, 0.4);
    twist(model);
    const float axes[4][3] = {
        {0.05f, 0.12f, 0.09f}, {0.15f, 0.06f, 0.1f}, {0.11f, 0.03f, 0.07f}, {0.2f, 0.14f, 0.05f}};
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) model.log_scales[i * 3 + k] = std::log(axes[i][k]);
    for (size_t i = 0; i < model.sh.size(); ++i)
      model.sh[i] = 0.4f * std::sin(1.7f * static_cast<float>(i));
  }

  // The term's value at `m`, and with `grads` its gradient as the training loop assembles it.
  double value(LossTerm& term, const GaussianModel& m, ModelGrads* grads = nullptr) const {
    RenderSettings s;
    s.min_alpha = 0;  // every contribution counted: small changes never move one in or out
    term.request(s);
    const RenderOutput out = render(m, cam, pose, s);
    RenderGrads image;
    ModelGrads own;
    own.reset(m);
    const double v = term.evaluate(StepRender{m, cam, pose, target, out}, image, own);
    if (grads) {
      *grads = own;
      render_backward(m, cam, pose, s, out, image, *grads);
    }
    return v;
  }
};

// Which of the model's parameters a term's gradient covers (the edge-extent term charges the
// scales alone, by design: depth_edge_extent.hpp).
struct Reaches {
  bool geometry = true;  // means, quaternions and opacities besides the scales
  bool sh = false;
};

// Central differences of the term's value on every entry of the parameters its gradient covers.
void check_term_gradient(const TermScene& scene, LossTerm& term, Reaches reaches) {
  const GaussianModel& m = scene.model;
  ModelGrads g;
  const double loss = scene.value(term, m, &g);
  INFO(term.name() << ": value " << loss);
  CHECK(loss > 0);
  const auto check = [&](std::vector<float> GaussianModel::*param,
                         std::vector<float> ModelGrads::*grad, const char* name) {
    double largest = 0;
    for (size_t k = 0; k < (m.*param).size(); ++k) {
      const double eps = 1e-3;
      GaussianModel up = m, down = m;
      (up.*param)[k] += float(eps);
      (down.*param)[k] -= float(eps);
      const double fd = (scene.value(term, up) - scene.value(term, down)) / (2 * eps);
      INFO(name << "[" << k << "]: analytic " << (g.*grad)[k] << ", central difference " << fd);
      // The margin covers the float render's rounding in the SSIM windows' differences.
      CHECK((g.*grad)[k] == Approx(fd).margin(2e-4).epsilon(0.03));
      largest = std::max(largest, std::abs(fd));
    }
    return largest;
  };
  // The term reaches the model: some gradient is far above the tolerance.
  double largest = check(&GaussianModel::log_scales, &ModelGrads::log_scales, "scales");
  if (reaches.geometry) {
    largest = std::max(largest, check(&GaussianModel::means, &ModelGrads::means, "means"));
    largest = std::max(largest, check(&GaussianModel::quats, &ModelGrads::quats, "quats"));
    largest = std::max(
        largest, check(&GaussianModel::opacity_logits, &ModelGrads::opacity_logits, "opacity"));
  }
  if (reaches.sh) largest = std::max(largest, check(&GaussianModel::sh, &ModelGrads::sh, "sh"));
  CHECK(largest > 1e-3);
}

// An Image term's gradient against central differences of its value in the rendered channel
// itself: the normal term's value is not a smooth function of the model (a pixel joins its mean
// when its rendered normal's length passes 1e-6), its image gradient is.
void check_image_gradient(const TermScene& scene, LossTerm& term,
                          std::vector<float> RenderOutput::*channel,
                          std::vector<float> RenderGrads::*grad) {
  RenderSettings s;
  s.min_alpha = 0;
  term.request(s);
  const RenderOutput out = render(scene.model, scene.cam, scene.pose, s);
  const auto value = [&](const RenderOutput& o, RenderGrads* g) {
    RenderGrads image;
    ModelGrads model;
    const double v = term.evaluate(StepRender{scene.model, scene.cam, scene.pose, scene.target, o},
                                   image, model);
    if (g) *g = image;
    return v;
  };
  RenderGrads analytic;
  CHECK(value(out, &analytic) > 0);
  double largest = 0;
  const std::vector<float>& rendered = out.*channel;
  for (size_t k = 0; k < rendered.size(); k += 7) {
    // Only where the model draws: a perturbation elsewhere would move the pixel into the mean.
    const size_t p = k / 3 * 3;
    if (std::hypot(rendered[p], rendered[p + 1], rendered[p + 2]) < 0.05) continue;
    RenderOutput up = out, down = out;
    (up.*channel)[k] += 1e-3f;
    (down.*channel)[k] -= 1e-3f;
    const double fd = (value(up, nullptr) - value(down, nullptr)) / 2e-3;
    INFO("entry " << k << ": analytic " << (analytic.*grad)[k] << ", central difference " << fd);
    CHECK((analytic.*grad)[k] == Approx(fd).margin(1e-5).epsilon(0.03));
    largest = std::max(largest, std::abs(fd));
  }
  CHECK(largest > 1e-5);
}

// The term of that factory with its weight set to 1 (0 would switch it off).
std::unique_ptr<LossTerm> make_term(std::unique_ptr<LossTerm> (*factory)(const ReconstructOptions&,
                                                                         const TermSetup&),
                                    const TermScene& scene, ReconstructOptions o = {}) {
  o.depth_weight = o.normal_weight = o.scale_weight = 1;
  o.edge_extent_weight = o.line_of_sight_weight = 1;
  o.floaters.tolerance = 0.03;
  auto term = factory(o, TermSetup{scene.observations});
  REQUIRE(term);
  CHECK(term->weight() == 1);
  return term;
}

}  // namespace

TEST_CASE("loss term gradients: photometric", "[splat][terms]") {
  const TermScene scene;
  auto term = make_term(photometric_term, scene);
  CHECK(term->stage() == TermStage::Image);
  check_term_gradient(scene, *term, Reaches{true, true});
}

TEST_CASE("loss term gradients: depth", "[splat][terms]") {
  const TermScene scene;
  auto term = make_term(depth_term, scene);
  CHECK(term->stage() == TermStage::Image);
  check_term_gradient(scene, *term, Reaches{});
}

TEST_CASE("loss term gradients: normal", "[splat][terms]") {
  const TermScene scene;
  auto term = make_term(normal_term, scene);
  CHECK(term->stage() == TermStage::Image);
  check_image_gradient(scene, *term, &RenderOutput::normal, &RenderGrads::normal);
}

TEST_CASE("loss term gradients: flatness", "[splat][terms]") {
  const TermScene scene;
  auto term = make_term(flatness_term, scene);
  CHECK(term->stage() == TermStage::Model);
  check_term_gradient(scene, *term, Reaches{});
}

TEST_CASE("loss term gradients: edge extent", "[splat][terms]") {
  const TermScene scene;
  auto term = make_term(edge_extent_term, scene);
  CHECK(term->stage() == TermStage::Model);
  check_term_gradient(scene, *term, Reaches{false, false});
}

TEST_CASE("loss term gradients: line of sight, by centre and by ray depth", "[splat][terms]") {
  const TermScene scene;
  auto term = make_term(line_of_sight_term, scene);
  CHECK(term->stage() == TermStage::Ray);
  check_term_gradient(scene, *term, Reaches{});
  ReconstructOptions ray;
  ray.floaters.ray_depth = true;
  check_term_gradient(scene, *make_term(line_of_sight_term, scene, ray), Reaches{});
}

TEST_CASE("the options switch terms on, in the order their values are summed", "[splat][terms]") {
  const TermScene scene;
  ReconstructOptions o;
  const auto names = [&](const ReconstructOptions& options) {
    std::vector<std::string> out;
    for (const auto& term : make_loss_terms(options, TermSetup{scene.observations}))
      out.push_back(term->name());
    return out;
  };
  // The defaults: photometric, depth 0.2, normal 0.1, flatness 0.01.
  CHECK(names(o) == std::vector<std::string>{"photometric", "depth", "normal", "flatness"});
  apply_recipe(o, Recipe::DepthPrior);
  CHECK(names(o) == std::vector<std::string>{"photometric", "depth", "normal", "flatness",
                                             "edge_extent", "line_of_sight"});
  o.depth_weight = o.normal_weight = o.scale_weight = 0;
  o.edge_extent_weight = o.line_of_sight_weight = 0;
  CHECK(names(o) == std::vector<std::string>{"photometric"});
}

TEST_CASE("a term joins on its schedule and where its target exists", "[splat][terms]") {
  const TermScene scene;
  ReconstructOptions o;
  o.line_of_sight_weight = 1;
  o.line_of_sight_start = 0.5;
  const auto sight = line_of_sight_term(o, TermSetup{scene.observations});
  CHECK_FALSE(sight->applies(49, 100, scene.target));
  CHECK(sight->applies(50, 100, scene.target));
  TargetImages no_prior = scene.target;
  no_prior.depth = cv::Mat();
  CHECK_FALSE(sight->applies(60, 100, no_prior));
  CHECK(TermSchedule{0.2, 3}.active(21, 100));
  CHECK_FALSE(TermSchedule{0.2, 3}.active(22, 100));
  CHECK_FALSE(TermSchedule{0.2, 3}.active(18, 100));
}
