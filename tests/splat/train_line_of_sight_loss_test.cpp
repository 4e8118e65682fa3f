// The line-of-sight loss against hand-placed Gaussians in front of, straddling, on and behind an
// observed wall: each term's value from rendered opacities, the front term zero behind the surface,
// the gradients of both terms against finite differences, and the same sums on one thread.
#include <cmath>

#include <tbb/global_control.h>

#include "nodes/splat/line_of_sight_loss.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A 40x30 camera (focal 40) at the origin looking down +z; its prior observes a wall at 4 m on the
// left (columns 0-19) and an object at 1.5 m on the right; the top-left 4x4 pixels have no prior.
struct Scene {
  Camera cam = test::centred_pinhole(40, 30, 40);
  Pose pose;
  cv::Mat1f depth;
  Scene() : depth(30, 40, 4.f) {
    depth(cv::Rect(20, 0, 20, 30)) = 1.5f;
    depth(cv::Rect(0, 0, 4, 4)) = 0.f;
  }
  // Every contribution counted (min_alpha 0), so small changes never move one in or out.
  RenderOutput forward(const GaussianModel& m) const {
    RenderSettings s;
    s.rgb = false;
    s.alpha = true;
    s.min_alpha = 0;
    return render(m, cam, pose, s);
  }
  // front_scale x front + behind_scale x behind, the gradient of the same into grads.
  double loss(const GaussianModel& m, ModelGrads* grads = nullptr, double front_scale = 1.0,
              double behind_scale = 0.0) const {
    const LineOfSightLoss l =
        line_of_sight_loss(m, cam, pose, depth, forward(m), 0.03, front_scale, behind_scale, grads);
    return front_scale * l.front + behind_scale * l.behind;
  }
  // Gaussian i centred on pixel (u, v) at depth z, isotropic scale s, opacity o.
  void place(GaussianModel& m, int i, double u, double v, double z, double s, double o) const {
    m.means[i * 3] = float((u - cam.cx) / cam.fx * z);
    m.means[i * 3 + 1] = float((v - cam.cy) / cam.fy * z);
    m.means[i * 3 + 2] = float(z);
    for (int k = 0; k < 3; ++k) m.log_scales[i * 3 + k] = float(std::log(s));
    m.quats[i * 4] = 1.f;
    m.opacity_logits[i] = float(std::log(o / (1 - o)));
  }
};

// Every parameter's analytic gradient in g against central differences of loss(model).
template <class Loss>
void check_gradients(const GaussianModel& m, const ModelGrads& g, Loss&& loss) {
  const auto check = [&](std::vector<float> GaussianModel::*param,
                         const std::vector<float> ModelGrads::*grad, const char* name) {
    const double eps = 1e-3;
    for (size_t k = 0; k < (m.*param).size(); ++k) {
      GaussianModel up = m, down = m;
      (up.*param)[k] += float(eps);
      (down.*param)[k] -= float(eps);
      const double fd = (loss(up) - loss(down)) / (2 * eps);
      INFO(name << "[" << k << "]: analytic " << (g.*grad)[k] << ", central difference " << fd);
      CHECK((g.*grad)[k] == Approx(fd).margin(2e-5).epsilon(0.03));
    }
  };
  check(&GaussianModel::means, &ModelGrads::means, "means");
  check(&GaussianModel::log_scales, &ModelGrads::log_scales, "log_scales");
  check(&GaussianModel::quats, &ModelGrads::quats, "quats");
  check(&GaussianModel::opacity_logits, &ModelGrads::opacity_logits, "opacity_logits");
}

}  // namespace

TEST_CASE("line-of-sight loss: the opacity drawn in front of the observed surface",
          "[splat][geometry]") {
  const Scene scene;
  const double observed = 40 * 30 - 16;

  // One Gaussian at 2 m in front of the wall, well inside the left half: every pixel with a prior
  // sees it in free space, so the loss is its rendered opacity over those pixels / their count.
  GaussianModel one;
  one.resize(1);
  scene.place(one, 0, 10.5, 15.5, 2.0, 0.08, 0.7);
  RenderSettings alpha_only;
  alpha_only.rgb = false;
  alpha_only.alpha = true;
  alpha_only.min_alpha = 0;
  const RenderOutput out = render(one, scene.cam, scene.pose, alpha_only);
  double drawn = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      if (scene.depth(y, x) > 0) drawn += out.alpha[size_t(y) * 40 + x];
  CHECK(drawn > 1);
  CHECK(scene.loss(one) == Approx(drawn / observed).epsilon(1e-4));

  // The same Gaussian on the wall (4 m, inside the 3% margin) or behind the object: nothing.
  GaussianModel on_wall = one;
  scene.place(on_wall, 0, 10.5, 15.5, 3.95, 0.16, 0.7);
  ModelGrads none;
  none.reset(on_wall);
  CHECK(scene.loss(on_wall, &none) == 0);
  CHECK(none.means == std::vector<float>(3, 0.f));
  CHECK(none.opacity_logits == std::vector<float>(1, 0.f));
}

TEST_CASE("line-of-sight loss: gradient against central differences", "[splat][geometry]") {
  const Scene scene;
  GaussianModel m;
  m.resize(4);
  scene.place(m, 0, 10.3, 14.8, 2.0, 0.12, 0.6);  // in front of the wall
  scene.place(m, 1, 19.6, 15.2, 3.0, 0.1,
              0.5);  // straddles: in front of the wall, behind the object
  scene.place(m, 2, 8.7, 9.4, 3.99, 0.2, 0.8);    // on the wall, behind Gaussian 0
  scene.place(m, 3, 29.5, 20.1, 1.0, 0.03, 0.4);  // in front of the object
  // Anisotropic and rotated, so that every quaternion and scale component has a gradient.
  const float scales1[] = {0.15f, 0.06f, 0.1f};
  for (int k = 0; k < 3; ++k) m.log_scales[3 + k] = std::log(scales1[k]);
  const Eigen::Quaternionf q =
      Eigen::Quaternionf(Eigen::AngleAxisf(0.6f, Eigen::Vector3f(0.3f, 0.2f, 1.f).normalized()));
  m.quats[4] = q.w(), m.quats[5] = q.x(), m.quats[6] = q.y(), m.quats[7] = q.z();
  m.quats[0] = 0.9f, m.quats[1] = 0.2f, m.quats[2] = -0.1f, m.quats[3] = 0.3f;
  m.log_scales[0] = std::log(0.05f);  // Gaussian 0 flat along x

  ModelGrads g;
  g.reset(m);
  const double loss = scene.loss(m, &g);
  CHECK(loss > 1e-3);
  // The Gaussian on the wall is never in front: no gradient at all.
  for (int k = 6; k < 9; ++k) CHECK(g.means[k] == 0.f);
  CHECK(g.opacity_logits[2] == 0.f);
  // More opacity in front of the surface costs more.
  CHECK(g.opacity_logits[0] > 0);

  check_gradients(m, g, [&](const GaussianModel& x) { return scene.loss(x); });

  // Scaled: the gradient scales, the value does not; the same sums, bit for bit, on one thread.
  ModelGrads twice;
  twice.reset(m);
  CHECK(line_of_sight_loss(m, scene.cam, scene.pose, scene.depth, scene.forward(m), 0.03, 2.0, 0.0,
                           &twice)
            .front == loss);
  for (size_t k = 0; k < g.means.size(); ++k) CHECK(twice.means[k] == Approx(2 * g.means[k]));
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  ModelGrads serial;
  serial.reset(m);
  CHECK(scene.loss(m, &serial) == loss);
  CHECK(serial.means == g.means);
  CHECK(serial.log_scales == g.log_scales);
}

TEST_CASE("line-of-sight loss: the weight drawn behind the observed surface, and its gradient",
          "[splat][geometry]") {
  const Scene scene;
  const double observed = 40 * 30 - 16;
  // A on the object's surface (1.5 m, right half), B behind it at 3 m: every pixel of B's footprint
  // observed the object, so B's weight there, (1 - a_A) a_B, is drawn behind the surface.
  GaussianModel m;
  m.resize(2);
  scene.place(m, 0, 30.2, 15.1, 1.5, 0.08, 0.6);
  scene.place(m, 1, 29.7, 14.6, 3.0, 0.16, 0.7);
  const auto alpha_of = [&](int i) {
    RenderSettings alpha_only;
    alpha_only.rgb = false;
    alpha_only.alpha = true;
    alpha_only.min_alpha = 0;
    return render(m.subset({size_t(i)}), scene.cam, scene.pose, alpha_only).alpha;
  };
  const std::vector<float> a = alpha_of(0), b = alpha_of(1);
  double behind = 0;
  for (size_t p = 0; p < a.size(); ++p) behind += (1.0 - a[p]) * b[p];
  const LineOfSightLoss l =
      line_of_sight_loss(m, scene.cam, scene.pose, scene.depth, scene.forward(m), 0.03, 1.0, 1.0);
  CHECK(behind > 1);
  CHECK(l.behind == Approx(behind / observed).epsilon(1e-4));
  CHECK(l.front == Approx(0).margin(1e-6));  // B's tail reaches the wall's half, 3 px out
  // Without the behind term it is neither computed nor differentiated.
  ModelGrads off;
  off.reset(m);
  CHECK(line_of_sight_loss(m, scene.cam, scene.pose, scene.depth, scene.forward(m), 0.03, 0.0, 0.0,
                           &off)
            .behind == 0);
  CHECK(off.opacity_logits == std::vector<float>(2, 0.f));
  // The gradient: more opacity behind costs, more opacity on the surface in front hides it.
  ModelGrads g;
  g.reset(m);
  scene.loss(m, &g, 0.0, 1.0);
  CHECK(g.opacity_logits[1] > 0);
  CHECK(g.opacity_logits[0] < 0);

  // Both terms at once on Gaussians in front of, on and behind both surfaces, anisotropic and
  // rotated, against central differences.
  GaussianModel all;
  all.resize(5);
  scene.place(all, 0, 10.3, 14.8, 2.0, 0.12, 0.6);   // in front of the wall
  scene.place(all, 1, 19.6, 15.2, 3.0, 0.1, 0.5);    // in front of the wall, behind the object
  scene.place(all, 2, 8.7, 9.4, 3.99, 0.2, 0.5);     // on the wall, behind Gaussian 0
  scene.place(all, 3, 30.5, 20.1, 1.48, 0.05, 0.6);  // on the object
  scene.place(all, 4, 29.2, 19.3, 2.5, 0.12, 0.7);   // behind the object, behind Gaussian 3
  const float scales1[] = {0.15f, 0.06f, 0.1f};
  for (int k = 0; k < 3; ++k) all.log_scales[3 + k] = std::log(scales1[k]);
  const Eigen::Quaternionf q =
      Eigen::Quaternionf(Eigen::AngleAxisf(0.6f, Eigen::Vector3f(0.3f, 0.2f, 1.f).normalized()));
  all.quats[4] = q.w(), all.quats[5] = q.x(), all.quats[6] = q.y(), all.quats[7] = q.z();
  all.quats[16] = 0.9f, all.quats[17] = 0.2f, all.quats[18] = -0.1f, all.quats[19] = 0.3f;
  all.log_scales[12] = std::log(0.06f);
  ModelGrads both;
  both.reset(all);
  const double value = scene.loss(all, &both, 0.6, 0.8);
  CHECK(value > 1e-3);
  check_gradients(all, both,
                  [&](const GaussianModel& x) { return scene.loss(x, nullptr, 0.6, 0.8); });
  // The same sums, bit for bit, on one thread.
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  ModelGrads serial;
  serial.reset(all);
  CHECK(scene.loss(all, &serial, 0.6, 0.8) == value);
  CHECK(serial.means == both.means);
  CHECK(serial.opacity_logits == both.opacity_logits);
}
