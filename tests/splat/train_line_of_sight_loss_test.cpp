// The line-of-sight loss against hand-placed Gaussians in front of,
// straddling and on an observed wall: their values from the rendered opacity, what lies behind the
// surface left out, their gradients against finite differences, and the same sums on one thread.
#include <cmath>

#include <tbb/global_control.h>

#include "nodes/splat/line_of_sight_loss.hpp"
#include "tests/splat/pinhole_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// The pinhole scene, with a prior that observes a wall at 4 m on the left (columns 0-19) and an
// object at 1.5 m on the right; the top-left 4x4 pixels have no prior.
struct SightScene : test::PinholeScene {
  cv::Mat1f depth;
  SightScene() : depth(30, 40, 4.f) {
    depth(cv::Rect(20, 0, 20, 30)) = 1.5f;
    depth(cv::Rect(0, 0, 4, 4)) = 0.f;
  }
  double loss(const GaussianModel& m, ModelGrads* grads = nullptr) const {
    return line_of_sight_loss(m, cam, pose, depth, forward(m), 0.03, 1.0, grads);
  }
  // The model's rendered opacity summed over the pixels with a prior.
  double drawn(const GaussianModel& m) const {
    const RenderOutput out = forward(m);
    double sum = 0;
    for (int y = 0; y < depth.rows; ++y)
      for (int x = 0; x < depth.cols; ++x)
        if (depth(y, x) > 0) sum += out.alpha[size_t(y) * depth.cols + x];
    return sum;
  }
};

}  // namespace

TEST_CASE("line-of-sight loss: the opacity drawn in front of the observed surface",
          "[splat][geometry]") {
  const SightScene scene;
  const double observed = 40 * 30 - 16;

  // One Gaussian at 2 m in front of the wall, well inside the left half: every pixel with a prior
  // sees it in free space, so the loss is its rendered opacity over those pixels / their count.
  GaussianModel one;
  one.resize(1);
  scene.place(one, 0, 10.5, 15.5, 2.0, 0.08, 0.7);
  CHECK(scene.drawn(one) > 1);
  CHECK(scene.loss(one) == Approx(scene.drawn(one) / observed).epsilon(1e-4));
  // No gradient at all for a single Gaussian.
  const auto none = [](const ModelGrads& g) {
    return g.means == std::vector<float>(3, 0.f) && g.opacity_logits == std::vector<float>(1, 0.f);
  };

  // The same Gaussian on the wall (4 m, inside the 3% margin) or behind the object: nothing.
  GaussianModel on_wall = one;
  scene.place(on_wall, 0, 10.5, 15.5, 3.95, 0.16, 0.7);
  ModelGrads on;
  on.reset(on_wall);
  CHECK(scene.loss(on_wall, &on) == 0);
  CHECK(none(on));

  // A view without any prior observes nothing: no loss and no gradient, whatever is drawn.
  const cv::Mat1f no_prior(30, 40, 0.f);
  ModelGrads unobserved;
  unobserved.reset(one);
  CHECK(line_of_sight_loss(one, scene.cam, scene.pose, no_prior, scene.forward(one), 0.03, 1.0,
                           &unobserved) == 0);
  CHECK(none(unobserved));
}

TEST_CASE("line-of-sight loss: gradient against central differences", "[splat][geometry]") {
  const SightScene scene;
  GaussianModel m;
  m.resize(4);
  scene.place(m, 0, 10.3, 14.8, 2.0, 0.12, 0.6);  // in front of the wall
  scene.place(m, 1, 19.6, 15.2, 3.0, 0.1,
              0.5);  // straddles: in front of the wall, behind the object
  scene.place(m, 2, 8.7, 9.4, 3.99, 0.2, 0.8);    // on the wall, behind Gaussian 0
  scene.place(m, 3, 29.5, 20.1, 1.0, 0.03, 0.4);  // in front of the object
  scene.twist(m);

  ModelGrads g;
  g.reset(m);
  const double loss = scene.loss(m, &g);
  CHECK(loss > 1e-3);
  // The Gaussian on the wall is never in front: no gradient at all.
  for (int k = 6; k < 9; ++k) CHECK(g.means[k] == 0.f);
  CHECK(g.opacity_logits[2] == 0.f);
  // More opacity in front of the surface costs more.
  CHECK(g.opacity_logits[0] > 0);

  using Loss = double (SightScene::*)(const GaussianModel&, ModelGrads*) const;
  const auto check = [&](Loss f, const ModelGrads& analytic,
                         std::vector<float> GaussianModel::*param,
                         std::vector<float> ModelGrads::*grad, const char* name, double eps) {
    for (size_t k = 0; k < (m.*param).size(); ++k) {
      GaussianModel up = m, down = m;
      (up.*param)[k] += float(eps);
      (down.*param)[k] -= float(eps);
      const double fd = ((scene.*f)(up, nullptr) - (scene.*f)(down, nullptr)) / (2 * eps);
      INFO(name << "[" << k << "]: analytic " << (analytic.*grad)[k] << ", central difference "
                << fd);
      CHECK((analytic.*grad)[k] == Approx(fd).margin(2e-5).epsilon(0.03));
    }
  };
  const auto check_all = [&](Loss f, const ModelGrads& analytic) {
    check(f, analytic, &GaussianModel::means, &ModelGrads::means, "means", 1e-3);
    check(f, analytic, &GaussianModel::log_scales, &ModelGrads::log_scales, "log_scales", 1e-3);
    check(f, analytic, &GaussianModel::quats, &ModelGrads::quats, "quats", 1e-3);
    check(f, analytic, &GaussianModel::opacity_logits, &ModelGrads::opacity_logits,
          "opacity_logits", 1e-3);
  };
  check_all(&SightScene::loss, g);

  // Scaled: the gradient scales, the value does not; the same sums, bit for bit, on one thread.
  ModelGrads twice;
  twice.reset(m);
  CHECK(line_of_sight_loss(m, scene.cam, scene.pose, scene.depth, scene.forward(m), 0.03, 2.0,
                           &twice) == loss);
  for (size_t k = 0; k < g.means.size(); ++k) CHECK(twice.means[k] == Approx(2 * g.means[k]));
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  ModelGrads serial;
  serial.reset(m);
  CHECK(scene.loss(m, &serial) == loss);
  CHECK(serial.means == g.means);
  CHECK(serial.log_scales == g.log_scales);
}
