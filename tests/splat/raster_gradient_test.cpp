// Finite-difference checks of render_backward for every rendered channel and every parameter kind.
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "tests/splat/raster_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// L = sum over rendered channels of <weights, channel>, accumulated in double.
struct LinearLoss {
  RenderGrads weights;
  double operator()(const RenderOutput& out) const {
    double L = 0;
    auto dot = [&](const std::vector<float>& w, const auto& x) {
      for (size_t i = 0; i < w.size(); ++i) L += double(w[i]) * x[i];
    };
    dot(weights.rgb, out.rgb);
    dot(weights.depth, out.depth);
    dot(weights.normal, out.normal);
    dot(weights.alpha, out.alpha);
    dot(weights.features, out.features);
    return L;
  }
};

std::vector<float> random_vector(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<float> v(n);
  for (float& x : v) x = u(rng);
  return v;
}

struct Kind {
  std::string name;
  std::vector<float> GaussianModel::*param;
  std::vector<float> ModelGrads::*grad;
  float eps;
};

// Compares the analytic gradient of every parameter with a central difference; the error over
// the whole parameter block, relative to the gradient's norm, must stay under `tolerance` (float
// rounding of the difference quotient; a wrong term gives errors of 1e-2 and more).
void check_gradients(const test::RasterScene& scene, const RenderSettings& settings, uint32_t seed,
                     double tolerance = 2e-3) {
  const RenderOutput out = render(scene.model, scene.camera, scene.pose, settings);
  std::mt19937 rng(seed);
  LinearLoss loss;
  if (!out.rgb.empty()) loss.weights.rgb = random_vector(out.rgb.size(), rng);
  if (!out.depth.empty()) loss.weights.depth = random_vector(out.depth.size(), rng);
  if (settings.normalize_depth) {
    // Normalised depth is S / A; where the coverage A is tiny it is ill-conditioned and jumps to
    // 0 below A = 1e-6, so the check (like a depth loss) weights only covered pixels.
    RenderSettings coverage = settings;
    coverage.alpha = true;
    const std::vector<float> alpha = render(scene.model, scene.camera, scene.pose, coverage).alpha;
    for (size_t i = 0; i < alpha.size(); ++i)
      if (alpha[i] < 0.05f) loss.weights.depth[i] = 0.f;
  }
  if (!out.normal.empty()) loss.weights.normal = random_vector(out.normal.size(), rng);
  if (!out.alpha.empty()) loss.weights.alpha = random_vector(out.alpha.size(), rng);
  if (!out.features.empty()) loss.weights.features = random_vector(out.features.size(), rng);
  if (settings.feature_pixels) {
    // A feature objective's loss: the features are read at the requested pixels only.
    std::vector<float> sparse(loss.weights.features.size(), 0.f);
    const size_t D = out.feature_dim;
    for (const uint32_t p : *settings.feature_pixels)
      for (size_t f = 0; f < D; ++f) sparse[p * D + f] = loss.weights.features[p * D + f];
    loss.weights.features = sparse;
  }
  ModelGrads grads;
  grads.reset(scene.model);
  render_backward(scene.model, scene.camera, scene.pose, settings, out, loss.weights, grads);

  const std::vector<Kind> kinds = {
      {"means", &GaussianModel::means, &ModelGrads::means, 2e-3f},
      {"log_scales", &GaussianModel::log_scales, &ModelGrads::log_scales, 2e-3f},
      {"quats", &GaussianModel::quats, &ModelGrads::quats, 2e-3f},
      {"opacity_logits", &GaussianModel::opacity_logits, &ModelGrads::opacity_logits, 1e-2f},
      {"sh", &GaussianModel::sh, &ModelGrads::sh, 1e-2f},
      {"features", &GaussianModel::features, &ModelGrads::features, 1e-2f},
  };
  for (const Kind& kind : kinds) {
    GaussianModel model = scene.model;
    std::vector<float>& p = model.*(kind.param);
    const std::vector<float>& analytic = grads.*(kind.grad);
    double err2 = 0, norm2 = 0;
    for (size_t i = 0; i < p.size(); ++i) {
      const float x = p[i];
      p[i] = x + kind.eps;
      const float hi = p[i];
      const double L_hi = loss(render(model, scene.camera, scene.pose, settings));
      p[i] = x - kind.eps;
      const float lo = p[i];
      const double L_lo = loss(render(model, scene.camera, scene.pose, settings));
      p[i] = x;
      const double fd = (L_hi - L_lo) / (double(hi) - double(lo));
      err2 += (fd - analytic[i]) * (fd - analytic[i]);
      norm2 += fd * fd;
    }
    INFO("parameter " << kind.name << ": |fd| = " << std::sqrt(norm2)
                      << ", |fd - analytic| = " << std::sqrt(err2));
    // Blocks a channel does not depend on have an exactly zero difference quotient.
    if (norm2 == 0) {
      for (float g : analytic) REQUIRE(g == 0.f);
    } else {
      CHECK(std::sqrt(err2) < tolerance * std::sqrt(norm2));
    }
  }
}

RenderSettings only(bool rgb, bool depth, bool normal, bool alpha, bool features) {
  RenderSettings s;
  s.rgb = rgb;
  s.depth = depth;
  s.normal = normal;
  s.alpha = alpha;
  s.features = features;
  s.min_alpha = 0.f;  // the 1/255 skip is a discontinuity finite differences cannot follow
  return s;
}

}  // namespace

TEST_CASE("raster: features at requested pixels only are exact there and change nothing else",
          "[splat][raster]") {
  // 64 x 48: 4 x 3 tiles; pixels in 3 of the 48 rows.
  const test::RasterScene scene = test::random_raster_scene(200, 1, 16, 11, 64, 48);
  RenderSettings full;
  full.depth = full.normal = full.alpha = full.features = true;
  RenderSettings sparse = full;
  const std::vector<uint32_t> pixels = {5 * 64 + 7, 5 * 64 + 60, 30 * 64 + 33, 47 * 64 + 63};
  sparse.feature_pixels = std::make_shared<const std::vector<uint32_t>>(pixels);
  const RenderOutput a = render(scene.model, scene.camera, scene.pose, full);
  const RenderOutput b = render(scene.model, scene.camera, scene.pose, sparse);
  CHECK(a.rgb == b.rgb);
  CHECK(a.depth == b.depth);
  CHECK(a.normal == b.normal);
  CHECK(a.alpha == b.alpha);
  for (const uint32_t p : pixels)
    for (int f = 0; f < 16; ++f) CHECK(b.features[p * 16 + f] == a.features[p * 16 + f]);
  // A row with no requested pixel got no features; the full render has them there.
  double full_row = 0, sparse_row = 0;
  for (int x = 0; x < 64; ++x) {
    full_row += std::abs(a.features[(20 * 64 + x) * 16]);
    sparse_row += std::abs(b.features[(20 * 64 + x) * 16]);
  }
  CHECK(full_row > 0);
  CHECK(sparse_row == 0);
  // The same gradient from either forward pass (the backward reads only its raster state).
  std::mt19937 rng(3);
  RenderGrads g;
  g.rgb = random_vector(a.rgb.size(), rng);
  g.features.assign(a.features.size(), 0.f);
  for (const uint32_t p : pixels)
    for (int f = 0; f < 16; ++f) g.features[p * 16 + f] = float(f) - 7.5f;
  ModelGrads from_full, from_sparse;
  from_full.reset(scene.model);
  from_sparse.reset(scene.model);
  render_backward(scene.model, scene.camera, scene.pose, full, a, g, from_full);
  render_backward(scene.model, scene.camera, scene.pose, sparse, b, g, from_sparse);
  CHECK(from_full.means == from_sparse.means);
  CHECK(from_full.opacity_logits == from_sparse.opacity_logits);
  CHECK(from_full.features == from_sparse.features);
  // A pixel outside the image is an error, not a write past the buffer.
  sparse.feature_pixels = std::make_shared<const std::vector<uint32_t>>(1, 64 * 48);
  CHECK_THROWS_AS(render(scene.model, scene.camera, scene.pose, sparse), InputError);
}

TEST_CASE("raster: gradients of each channel match central differences", "[splat][raster]") {
  const test::RasterScene scene = test::random_raster_scene(16, 3, 4, 7);
  SECTION("rgb, SH degree 3, with background") {
    RenderSettings s = only(true, false, false, false, false);
    s.background = Eigen::Vector3f(0.2f, 0.5f, 0.9f);
    check_gradients(scene, s, 1);
  }
  SECTION("rgb, active SH degree 1 of 3") {
    RenderSettings s = only(true, false, false, false, false);
    s.sh_degree = 1;
    check_gradients(scene, s, 2);
  }
  SECTION("expected depth") {
    check_gradients(scene, only(false, true, false, false, false), 3);
  }
  SECTION("normalised depth") {
    RenderSettings s = only(false, true, false, false, false);
    s.normalize_depth = true;
    // d / alpha at pixels with alpha down to 0.05 scales the quotient's rounding by up to 20:
    // 4.2e-3 for the means under clang's rounding (below 2e-3 under g++'s).
    check_gradients(scene, s, 4, 6e-3);
  }
  SECTION("normal") {
    check_gradients(scene, only(false, false, true, false, false), 5);
  }
  SECTION("alpha") {
    check_gradients(scene, only(false, false, false, true, false), 6);
  }
  SECTION("features") {
    check_gradients(scene, only(false, false, false, false, true), 7);
  }
  SECTION("Gaussians beyond the Jacobian's frustum clamp (x/z, y/z > 1.3 tan(fov/2))") {
    // Two wide Gaussians centred outside the image whose footprints still reach into it: the
    // Jacobian uses the clamped x/z or y/z, whose derivative differs from the unclamped one.
    test::RasterScene clamped = scene;
    const double z = 3.0;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d cam =
          i == 0 ? Eigen::Vector3d(0.95 * z, 0.1, z) : Eigen::Vector3d(-0.2, -0.8 * z, z);
      const Eigen::Vector3d world = clamped.pose.R.transpose() * (cam - clamped.pose.t);
      for (int k = 0; k < 3; ++k) {
        clamped.model.means[3 * i + k] = float(world[k]);
        clamped.model.log_scales[3 * i + k] = std::log(k == 2 ? 0.3f : 0.9f);
      }
    }
    RenderSettings s = only(true, true, true, true, true);
    check_gradients(clamped, s, 9);
  }
  SECTION("features read at three pixels of two tile rows (RenderSettings::feature_pixels)") {
    // The forward pass blends features only in those rows and the backward pass skips the
    // feature channels in every row without a feature gradient: both must stay exact.
    RenderSettings s = only(true, true, true, false, true);
    const int w = scene.camera.width;
    s.feature_pixels = std::make_shared<const std::vector<uint32_t>>(
        std::vector<uint32_t>{uint32_t(2 * w + 3), uint32_t(2 * w + 20), uint32_t(17 * w + 10)});
    check_gradients(scene, s, 10);
  }
  SECTION("all channels in one pass") {
    RenderSettings s = only(true, true, true, true, true);
    s.normalize_depth = true;
    s.background = Eigen::Vector3f(1.f, 0.f, 0.5f);
    check_gradients(scene, s, 8);
  }
}

TEST_CASE("raster: gradients with dense overlap", "[splat][raster]") {
  // 60 Gaussians on a small image overlap heavily, exercising transmittance recovery by division
  // over long lists; checked along a random direction in parameter space.
  const test::RasterScene scene = test::random_raster_scene(60, 2, 2, 11);
  RenderSettings s;
  s.min_alpha = 0.f;
  s.depth = s.normal = s.alpha = s.features = true;
  const RenderOutput out = render(scene.model, scene.camera, scene.pose, s);
  std::mt19937 rng(5);
  LinearLoss loss;
  loss.weights.rgb = random_vector(out.rgb.size(), rng);
  loss.weights.depth = random_vector(out.depth.size(), rng);
  loss.weights.normal = random_vector(out.normal.size(), rng);
  loss.weights.alpha = random_vector(out.alpha.size(), rng);
  loss.weights.features = random_vector(out.features.size(), rng);
  ModelGrads grads;
  grads.reset(scene.model);
  render_backward(scene.model, scene.camera, scene.pose, s, out, loss.weights, grads);
  for (const auto& member :
       {std::pair{&GaussianModel::means, &ModelGrads::means},
        std::pair{&GaussianModel::log_scales, &ModelGrads::log_scales},
        std::pair{&GaussianModel::quats, &ModelGrads::quats},
        std::pair{&GaussianModel::opacity_logits, &ModelGrads::opacity_logits}}) {
    // Plain variables, not a structured binding: C++17 lets no lambda capture one (clang
    // refuses, g++ accepts it as an extension).
    const auto param = member.first;
    const auto grad = member.second;
    const std::vector<float> dir = random_vector((scene.model.*param).size(), rng);
    const double eps = 1e-3;
    double analytic = 0;
    for (size_t i = 0; i < dir.size(); ++i) analytic += double(dir[i]) * (grads.*grad)[i];
    auto shifted = [&](double h) {
      GaussianModel m = scene.model;
      for (size_t i = 0; i < dir.size(); ++i) (m.*param)[i] += float(h * dir[i]);
      return loss(render(m, scene.camera, scene.pose, s));
    };
    const double fd = (shifted(eps) - shifted(-eps)) / (2 * eps);
    CHECK(std::abs(fd - analytic) < 1e-2 * std::abs(analytic));
  }
}

TEST_CASE("raster: the pose gradient matches central differences of a moved camera",
          "[splat][raster]") {
  // The view moved by a rotation w and a translation dt in its own frame (pose_correction.hpp):
  // R' = exp([w]x) R, t' = exp([w]x) t + dt. Every channel depends on it through the projected
  // means and covariances, and the colour through the SH view direction.
  const test::RasterScene scene = test::random_raster_scene(16, 3, 4, 7);
  const auto moved = [&](int k, double h) {
    Eigen::Vector3d w = Eigen::Vector3d::Zero(), dt = Eigen::Vector3d::Zero();
    (k < 3 ? w : dt)[k % 3] = h;
    const Eigen::Matrix3d rotation =
        h == 0 || k >= 3 ? Eigen::Matrix3d::Identity()
                         : Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    Pose p;
    p.R = rotation * scene.pose.R;
    p.t = rotation * scene.pose.t + dt;
    return p;
  };
  const auto check = [&](const RenderSettings& settings, uint32_t seed) {
    const RenderOutput out = render(scene.model, scene.camera, scene.pose, settings);
    std::mt19937 rng(seed);
    LinearLoss loss;
    if (!out.rgb.empty()) loss.weights.rgb = random_vector(out.rgb.size(), rng);
    if (!out.depth.empty()) loss.weights.depth = random_vector(out.depth.size(), rng);
    if (!out.alpha.empty()) loss.weights.alpha = random_vector(out.alpha.size(), rng);
    if (!out.features.empty()) loss.weights.features = random_vector(out.features.size(), rng);
    ModelGrads grads;
    grads.reset(scene.model);
    PoseGradient analytic;
    render_backward(scene.model, scene.camera, scene.pose, settings, out, loss.weights, grads,
                    &analytic);
    const double h = 1e-3;
    double err2 = 0, norm2 = 0;
    for (int k = 0; k < 6; ++k) {
      const double fd = (loss(render(scene.model, scene.camera, moved(k, h), settings)) -
                         loss(render(scene.model, scene.camera, moved(k, -h), settings))) /
                        (2 * h);
      INFO("pose coordinate " << k << ": fd " << fd << ", analytic " << analytic[k]);
      CHECK(std::abs(fd - analytic[k]) < 5e-3 * std::abs(fd) + 1e-3);
      err2 += (fd - analytic[k]) * (fd - analytic[k]);
      norm2 += fd * fd;
    }
    REQUIRE(norm2 > 0);
    CHECK(std::sqrt(err2) < 3e-3 * std::sqrt(norm2));
  };
  SECTION("rgb, SH degree 3 (the view direction moves with the camera centre)") {
    check(only(true, false, false, false, false), 21);
  }
  SECTION("depth, alpha and features") {
    check(only(false, true, false, true, true), 22);
  }
  SECTION("the model's gradients are those of a pass without the pose gradient") {
    RenderSettings s = only(true, true, true, true, true);
    const RenderOutput out = render(scene.model, scene.camera, scene.pose, s);
    std::mt19937 rng(23);
    RenderGrads weights;
    weights.rgb = random_vector(out.rgb.size(), rng);
    weights.depth = random_vector(out.depth.size(), rng);
    ModelGrads with, without;
    with.reset(scene.model);
    without.reset(scene.model);
    PoseGradient pose_grad;
    render_backward(scene.model, scene.camera, scene.pose, s, out, weights, with, &pose_grad);
    render_backward(scene.model, scene.camera, scene.pose, s, out, weights, without);
    CHECK(with.means == without.means);
    CHECK(with.sh == without.sh);
    CHECK(with.quats == without.quats);
  }
}
