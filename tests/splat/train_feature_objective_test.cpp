// The reconstruction's optional feature objective (feature_objective.hpp, Proto-SaGa Eq. 8): the
// gradient of the combined loss L_rec + w L_feat against central differences on a tiny scene,
// bit-identical geometry with w = 0, and joint training that lowers L_feat.
#include <cmath>
#include <random>

#include "nodes/splat/feature_objective.hpp"
#include "nodes/splat/losses.hpp"
#include "nodes/splat/reconstruct.hpp"
#include "tests/splat/raster_scene.hpp"
#include "tests/splat/train_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// L_feat = 0.5 mean over pixels of |F(p) - t(p)|^2, a smooth objective with a known gradient.
FeatureObjective quadratic_objective(int dim, double weight, const std::vector<float>& target) {
  FeatureObjective o;
  o.dim = dim;
  o.weight = weight;
  o.loss = [&target, dim](int, int, int w, int h, const float* f, float* grad) {
    const size_t n = size_t(w) * h * dim;
    double L = 0;
    for (size_t i = 0; i < n; ++i) {
      const double d = double(f[i]) - target[i % target.size()];
      L += 0.5 * d * d / (w * h);
      grad[i] = static_cast<float>(d / (w * h));
    }
    return L;
  };
  return o;
}

}  // namespace

TEST_CASE("feature objective: the combined loss's gradient matches central differences",
          "[splat]") {
  const test::RasterScene scene = test::random_raster_scene(12, 0, 3, 11);
  RenderSettings s;
  s.features = true;
  s.min_alpha = 0.f;  // the 1/255 skip is a discontinuity finite differences cannot follow
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  const int W = scene.camera.width, H = scene.camera.height;
  cv::Mat target(H, W, CV_32FC3);
  for (auto it = target.begin<cv::Vec3f>(); it != target.end<cv::Vec3f>(); ++it)
    *it = cv::Vec3f(u(rng), u(rng), u(rng));
  std::vector<float> feature_target(size_t(W) * H * 3);
  for (float& t : feature_target) t = u(rng) - 0.5f;
  const FeatureObjective objective = quadratic_objective(3, 0.7, feature_target);
  // D-SSIM only (lambda 1): smooth, so that central differences do not straddle an L1 kink.
  auto combined = [&](const GaussianModel& m, RenderGrads* grads) {
    RenderOutput out = render(m, scene.camera, scene.pose, s);
    cv::Mat grad;
    const double rec =
        photometric_loss(cv::Mat(H, W, CV_32FC3, out.rgb.data()), target, 1.0, &grad).value;
    RenderGrads g;
    const double feat = feature_objective_grads(objective, 0, 0, out, g);
    if (grads) {
      g.rgb.assign(grad.ptr<float>(), grad.ptr<float>() + grad.total() * 3);
      *grads = std::move(g);
    }
    return rec + objective.weight * feat;
  };
  RenderGrads rgrads;
  combined(scene.model, &rgrads);
  ModelGrads grads;
  grads.reset(scene.model);
  render_backward(scene.model, scene.camera, scene.pose, s,
                  render(scene.model, scene.camera, scene.pose, s), rgrads, grads);

  struct Kind {
    const char* name;
    std::vector<float> GaussianModel::*param;
    std::vector<float> ModelGrads::*grad;
    float eps;
  };
  for (const Kind& kind :
       {Kind{"means", &GaussianModel::means, &ModelGrads::means, 1e-3f},
        Kind{"opacity_logits", &GaussianModel::opacity_logits, &ModelGrads::opacity_logits, 1e-2f},
        Kind{"features", &GaussianModel::features, &ModelGrads::features, 1e-2f}}) {
    GaussianModel m = scene.model;
    std::vector<float>& p = m.*(kind.param);
    const std::vector<float>& analytic = grads.*(kind.grad);
    double err2 = 0, norm2 = 0;
    for (size_t i = 0; i < p.size(); ++i) {
      const float x = p[i];
      const float hi = p[i] = x + kind.eps;
      const double L_hi = combined(m, nullptr);
      const float lo = p[i] = x - kind.eps;
      const double L_lo = combined(m, nullptr);
      p[i] = x;
      const double fd = (L_hi - L_lo) / (double(hi) - double(lo));
      err2 += (fd - analytic[i]) * (fd - analytic[i]);
      norm2 += fd * fd;
    }
    INFO(kind.name << ": |fd| = " << std::sqrt(norm2) << ", |fd - analytic| = " << std::sqrt(err2));
    CHECK(norm2 > 0);
    CHECK(std::sqrt(err2) < 5e-3 * std::sqrt(norm2));
  }
}

TEST_CASE("feature objective: weight 0 leaves the reconstruction bit-identical, weight > 0 trains",
          "[splat][long]") {
  const Capture capture = test::rendered_capture();
  ReconstructOptions o;
  o.iterations = 60;
  o.init.pixel_stride = 1;
  o.init.footprint_factor = 2;
  o.density.start = 10;  // densification rounds inside the short run: features follow their rows
  o.density.interval = 20;
  o.seed = 3;
  const ReconstructResult plain = reconstruct(capture, o);

  const int dim = 2;
  const std::vector<float> feature_target = {0.3f, -0.2f};
  FeatureObjective objective = quadratic_objective(dim, 0.0, feature_target);
  objective.lr = 1e-2;
  int updates = 0;
  objective.update = [&](int) { ++updates; };
  objective.initialise = [](size_t, std::vector<float>& f) {
    for (size_t i = 0; i < f.size(); ++i) f[i] = (i % 3 == 0) ? 0.1f : -0.1f;
  };
  const ReconstructResult zero = reconstruct(capture, o, {}, &objective);
  CHECK(updates == 60);
  CHECK(zero.model.means == plain.model.means);
  CHECK(zero.model.log_scales == plain.model.log_scales);
  CHECK(zero.model.quats == plain.model.quats);
  CHECK(zero.model.opacity_logits == plain.model.opacity_logits);
  CHECK(zero.model.sh == plain.model.sh);
  CHECK(zero.loss_history == plain.loss_history);
  CHECK(zero.train_psnr == plain.train_psnr);
  REQUIRE(zero.model.feature_dim == dim);
  CHECK(zero.model.features.size() == zero.model.size() * dim);

  objective.weight = 0.5;
  const ReconstructResult joint = reconstruct(capture, o, {}, &objective);
  CHECK(joint.model.means != plain.model.means);  // the feature loss reaches the geometry
  CHECK(joint.final_loss.features > 0);
  // With weight 0 the features keep their initial values (zero gradient); trained, they reach
  // the target and the loss of the last steps falls far below.
  INFO("final feature loss " << joint.final_loss.features << ", untrained "
                             << zero.final_loss.features);
  CHECK(joint.final_loss.features < 0.6 * zero.final_loss.features);
  CHECK(joint.final_loss.total == Approx(joint.final_loss.term("photometric") +
                                         o.depth_weight * joint.final_loss.term("depth") +
                                         o.normal_weight * joint.final_loss.term("normal") +
                                         o.scale_weight * joint.final_loss.term("flatness") +
                                         0.5 * joint.final_loss.features));
}
