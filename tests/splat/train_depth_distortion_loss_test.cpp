// The depth distortion loss against hand-placed Gaussians: its value for two layers that cover
// the view (2 w1 w2 |ln z2 - ln z1|), zero for one layer, its gradient against central differences,
// and the same sums on one thread.
#include <cmath>

#include <tbb/global_control.h>

#include "nodes/splat/depth_distortion_loss.hpp"
#include "tests/splat/pinhole_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

struct DistortionScene : test::PinholeScene {
  double loss(const GaussianModel& m, ModelGrads* grads = nullptr) const {
    return depth_distortion_loss(m, cam, pose, forward(m), 1.0, grads);
  }
};

}  // namespace

TEST_CASE("depth distortion: two layers over the view cost 2 w1 w2 |ln z2 - ln z1|",
          "[splat][geometry]") {
  const DistortionScene scene;
  // Discs 100 times wider than the view: the alpha of each is its opacity to 1e-4 everywhere, so
  // every pixel blends w1 = 0.6, w2 = 0.5 (1 - 0.6).
  GaussianModel m;
  m.resize(2);
  scene.place(m, 0, 20, 15, 2.0, 200.0, 0.6);
  scene.place(m, 1, 20, 15, 3.0, 300.0, 0.5);
  const double expected = 2 * 0.6 * 0.5 * 0.4 * std::log(3.0 / 2.0);
  CHECK(scene.loss(m) == Approx(expected).epsilon(1e-3));

  // One layer, or two at the same depth, cost nothing.
  CHECK(scene.loss(m.subset({0})) == 0);
  GaussianModel same = m;
  same.means[5] = same.means[2];
  CHECK(scene.loss(same) == Approx(0).margin(1e-7));

  // The gradient draws the layers together: the near one back, the far one forward, and it fades
  // the second layer.
  ModelGrads g;
  g.reset(m);
  scene.loss(m, &g);
  CHECK(g.means[2] < 0);  // descending moves the near layer back (+z)...
  CHECK(g.means[5] > 0);  // ... and the far one forward
  CHECK(g.opacity_logits[1] > 0);
}

TEST_CASE("depth distortion: gradient against central differences", "[splat][geometry]") {
  const DistortionScene scene;
  GaussianModel m;
  m.resize(4);
  scene.place(m, 0, 10.3, 14.8, 2.0, 0.15, 0.6);
  scene.place(m, 1, 19.6, 15.2, 3.0, 0.12, 0.5);
  scene.place(m, 2, 12.7, 11.4, 3.9, 0.25, 0.8);
  scene.place(m, 3, 16.5, 16.1, 2.6, 0.1, 0.4);
  scene.twist(m);

  ModelGrads g;
  g.reset(m);
  const double loss = scene.loss(m, &g);
  CHECK(loss > 1e-3);
  const auto check = [&](std::vector<float> GaussianModel::*param,
                         std::vector<float> ModelGrads::*grad, const char* name, double eps) {
    for (size_t k = 0; k < (m.*param).size(); ++k) {
      GaussianModel up = m, down = m;
      (up.*param)[k] += float(eps);
      (down.*param)[k] -= float(eps);
      const double fd = (scene.loss(up) - scene.loss(down)) / (2 * eps);
      INFO(name << "[" << k << "]: analytic " << (g.*grad)[k] << ", central difference " << fd);
      CHECK((g.*grad)[k] == Approx(fd).margin(2e-5).epsilon(0.03));
    }
  };
  check(&GaussianModel::means, &ModelGrads::means, "means", 1e-3);
  check(&GaussianModel::log_scales, &ModelGrads::log_scales, "log_scales", 1e-3);
  check(&GaussianModel::quats, &ModelGrads::quats, "quats", 1e-3);
  check(&GaussianModel::opacity_logits, &ModelGrads::opacity_logits, "opacity_logits", 1e-3);

  // Scaled: the gradient scales, the value does not; the same sums, bit for bit, on one thread.
  ModelGrads twice;
  twice.reset(m);
  CHECK(depth_distortion_loss(m, scene.cam, scene.pose, scene.forward(m), 2.0, &twice) == loss);
  for (size_t k = 0; k < g.means.size(); ++k) CHECK(twice.means[k] == Approx(2 * g.means[k]));
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  ModelGrads serial;
  serial.reset(m);
  CHECK(scene.loss(m, &serial) == loss);
  CHECK(serial.means == g.means);
  CHECK(serial.log_scales == g.log_scales);
  CHECK(serial.opacity_logits == g.opacity_logits);
}
