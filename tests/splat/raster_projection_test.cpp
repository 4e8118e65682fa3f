// Projection against hand-computed cases, culling, degenerate input and thread-count determinism.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <tbb/global_control.h>

#include "nodes/splat/projection.hpp"
#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "runtime/node.hpp"
#include "tests/splat/raster_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

Camera hand_camera() {
  Camera c;
  c.width = 100;
  c.height = 80;
  c.fx = 100;
  c.fy = 120;
  c.cx = 50;
  c.cy = 40;
  return c;
}

GaussianModel one_gaussian(const Eigen::Vector3f& mean, const Eigen::Vector3f& scale,
                           const Eigen::Vector4f& quat) {
  GaussianModel m;
  m.resize(1);
  for (int k = 0; k < 3; ++k) {
    m.means[k] = mean[k];
    m.log_scales[k] = std::log(scale[k]);
  }
  for (int k = 0; k < 4; ++k) m.quats[k] = quat[k];
  m.opacity_logits[0] = 2.f;
  m.sh = {1.f, 1.f, 1.f};
  return m;
}

template <class Values>
bool all_finite(const Values& v) {
  for (float x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

TEST_CASE("raster: projection of one Gaussian matches the hand computation", "[splat][raster]") {
  const ViewTransform view(hand_camera(), Pose{});
  // Mean (0.2, -0.1, 2), identity pose: mean2d = (100 * 0.1 + 50, 120 * -0.05 + 40) = (60, 34).
  // J = [[50, 0, -5], [0, 60, 3]], Sigma = diag(0.01, 0.0025, 0.0004):
  // a = 2500 * 0.01 + 25 * 0.0004 + 0.3 = 25.31, b = -5 * 3 * 0.0004 = -0.006,
  // c = 3600 * 0.0025 + 9 * 0.0004 + 0.3 = 9.3036; lambda_max = 25.310002, radius ceil(15.093)
  // = 16.
  const float mean[3] = {0.2f, -0.1f, 2.f};
  const float log_scale[3] = {std::log(0.1f), std::log(0.05f), std::log(0.02f)};
  const float identity[4] = {1.f, 0.f, 0.f, 0.f};
  ProjectedGaussian p;
  REQUIRE(project_gaussian(view, mean, log_scale, identity, 0.01f, p));
  CHECK(p.mean2d.x() == Approx(60.f).epsilon(1e-6));
  CHECK(p.mean2d.y() == Approx(34.f).epsilon(1e-6));
  CHECK(p.cov2d[0] == Approx(25.31f).epsilon(1e-5));
  CHECK(p.cov2d[1] == Approx(-0.006f).epsilon(1e-4));
  CHECK(p.cov2d[2] == Approx(9.3036f).epsilon(1e-5));
  const float det = 25.31f * 9.3036f - 0.006f * 0.006f;
  CHECK(p.conic[0] == Approx(9.3036f / det).epsilon(1e-5));
  CHECK(p.conic[1] == Approx(0.006f / det).epsilon(1e-4));
  CHECK(p.conic[2] == Approx(25.31f / det).epsilon(1e-5));
  CHECK(p.radius == 16);
  CHECK(p.depth == Approx(2.f));
  // Shortest axis is z; it points away from the camera, so it is flipped.
  CHECK((p.normal - Eigen::Vector3f(0, 0, -1)).norm() < 1e-6f);

  // A 90 degree turn about z swaps the x and y scales (w, x, y, z convention); the quaternion need
  // not be unit: a = 2500 * 0.0025 + 0.01 + 0.3 = 6.56, c = 3600 * 0.01 + 0.0036 + 0.3 = 36.3036.
  const float turned[4] = {2.f * std::sqrt(0.5f), 0.f, 0.f, 2.f * std::sqrt(0.5f)};
  REQUIRE(project_gaussian(view, mean, log_scale, turned, 0.01f, p));
  CHECK(p.cov2d[0] == Approx(6.56f).epsilon(1e-5));
  CHECK(p.cov2d[2] == Approx(36.3036f).epsilon(1e-5));
  CHECK(p.radius == int(std::ceil(3.f * std::sqrt(36.3036f))));

  // The same point seen from a camera translated by t = (0, 0, 1): z = 3, mean2d = (56.67, 36).
  Pose moved;
  moved.t = Eigen::Vector3d(0, 0, 1);
  REQUIRE(
      project_gaussian(ViewTransform(hand_camera(), moved), mean, log_scale, identity, 0.01f, p));
  CHECK(p.mean2d.x() == Approx(50.f + 100.f * 0.2f / 3.f));
  CHECK(p.mean2d.y() == Approx(40.f - 120.f * 0.1f / 3.f));
  CHECK(p.depth == Approx(3.f));
}

TEST_CASE("raster: a single Gaussian renders its colour with alpha = o exp(-0.5 d^T conic d)",
          "[splat][raster]") {
  // Constant colour 0.5 + C0 * 1 wherever it is drawn; the blend weight has a closed form at
  // every pixel of the tiles its 3-sigma square (radius 16 around (60, 34)) touches, i.e. pixel
  // columns 32..79 and rows 16..63, and it is not drawn at all outside them.
  const GaussianModel model =
      one_gaussian({0.2f, -0.1f, 2.f}, {0.1f, 0.05f, 0.02f}, {1.f, 0.f, 0.f, 0.f});
  RenderSettings s;
  s.alpha = s.depth = true;
  s.min_alpha = 0.f;
  const RenderOutput out = render(model, hand_camera(), Pose{}, s);
  const double a = 25.31, b = -0.006, c = 9.3036, det = a * c - b * b;
  auto alpha_at = [&](int x, int y) {
    const double dx = 60.0 - (x + 0.5), dy = 34.0 - (y + 0.5);
    const double power = -0.5 * (c / det * dx * dx + a / det * dy * dy) - (-b / det) * dx * dy;
    return 1.0 / (1.0 + std::exp(-2.0)) * std::exp(power);
  };
  for (auto [x, y] : {std::pair{59, 33}, std::pair{62, 37}, std::pair{76, 33}, std::pair{59, 44}}) {
    const size_t pix = size_t(y) * 100 + x;
    CHECK(out.alpha[pix] == Approx(alpha_at(x, y)).epsilon(1e-5));
    CHECK(out.rgb[pix * 3] == Approx(alpha_at(x, y) * (0.5 + 0.28209479)).epsilon(1e-5));
    CHECK(out.depth[pix] == Approx(alpha_at(x, y) * 2.0).epsilon(1e-5));
  }
  CHECK(out.radii[0] == 16);
  CHECK(out.alpha[size_t(33) * 100 + 80] == 0.f);
  CHECK(out.alpha[size_t(33) * 100 + 31] == 0.f);
  CHECK(out.alpha[size_t(64) * 100 + 60] == 0.f);
  // With the default 1/255 threshold the faint tail at (59, 44) (alpha 0.0024) is skipped and the
  // brighter pixels are unchanged.
  REQUIRE(alpha_at(59, 44) < 1.0 / 255.0);
  RenderSettings defaults;
  defaults.alpha = true;
  const RenderOutput thresholded = render(model, hand_camera(), Pose{}, defaults);
  CHECK(thresholded.alpha[size_t(44) * 100 + 59] == 0.f);
  CHECK(thresholded.alpha[size_t(33) * 100 + 76] == out.alpha[size_t(33) * 100 + 76]);
  CHECK(thresholded.alpha[size_t(37) * 100 + 62] == out.alpha[size_t(37) * 100 + 62]);
}

TEST_CASE("raster: an empty view renders the background and has zero gradients",
          "[splat][raster]") {
  GaussianModel empty;
  empty.feature_dim = 3;
  RenderSettings s;
  s.depth = s.normal = s.alpha = s.features = true;
  s.background = Eigen::Vector3f(0.1f, 0.2f, 0.3f);
  const RenderOutput out = render(empty, hand_camera(), Pose{}, s);
  REQUIRE(out.rgb.size() == 100u * 80u * 3u);
  CHECK(out.rgb[0] == 0.1f);
  CHECK(out.rgb[3 * 4321 + 2] == 0.3f);
  for (float a : out.alpha) REQUIRE(a == 0.f);
  REQUIRE(out.features.size() == 100u * 80u * 3u);
  ModelGrads grads;
  grads.reset(empty);
  RenderGrads g;
  g.rgb.assign(out.rgb.size(), 1.f);
  render_backward(empty, hand_camera(), Pose{}, s, out, g, grads);
  CHECK(grads.means.empty());
}

TEST_CASE("raster: Gaussians behind the camera or the near plane are culled", "[splat][raster]") {
  for (float z : {-2.f, 0.f, 0.005f}) {
    const GaussianModel model = one_gaussian({0.f, 0.f, z}, {0.5f, 0.5f, 0.5f}, {1, 0, 0, 0});
    RenderSettings s;
    s.alpha = true;
    const RenderOutput out = render(model, hand_camera(), Pose{}, s);
    CHECK(out.radii[0] == 0);
    for (float a : out.alpha) REQUIRE(a == 0.f);
    ModelGrads grads;
    grads.reset(model);
    RenderGrads g;
    g.alpha.assign(out.alpha.size(), 1.f);
    render_backward(model, hand_camera(), Pose{}, s, out, g, grads);
    CHECK(grads.means == std::vector<float>{0.f, 0.f, 0.f});
    CHECK(grads.visible[0] == 0);
  }
}

TEST_CASE("raster: degenerate Gaussians produce no NaN", "[splat][raster]") {
  const float inf = std::numeric_limits<float>::infinity();
  const test::RasterScene scene = test::random_raster_scene(6, 1, 2, 3, 40, 30);
  GaussianModel model = scene.model;
  // Zero scales (log -inf and -100), a zero quaternion, a huge scale.
  for (int k = 0; k < 3; ++k) {
    model.log_scales[k] = -inf;
    model.log_scales[3 + k] = -100.f;
    model.log_scales[12 + k] = 60.f;
  }
  for (int k = 0; k < 4; ++k) model.quats[8 + k] = 0.f;
  model.log_scales[9] = -inf;  // one flat axis
  RenderSettings s;
  s.depth = s.normal = s.alpha = s.features = s.normalize_depth = true;
  const RenderOutput out = render(model, scene.camera, scene.pose, s);
  CHECK(all_finite(out.rgb));
  CHECK(all_finite(out.depth));
  CHECK(all_finite(out.normal));
  CHECK(all_finite(out.features));
  RenderGrads g;
  g.rgb.assign(out.rgb.size(), 1.f);
  g.depth.assign(out.depth.size(), 1.f);
  g.normal.assign(out.normal.size(), 1.f);
  g.alpha.assign(out.alpha.size(), 1.f);
  g.features.assign(out.features.size(), 1.f);
  ModelGrads grads;
  grads.reset(model);
  render_backward(model, scene.camera, scene.pose, s, out, g, grads);
  CHECK(all_finite(grads.means));
  CHECK(all_finite(grads.log_scales));
  CHECK(all_finite(grads.quats));
  CHECK(all_finite(grads.opacity_logits));
  CHECK(all_finite(grads.sh));
  CHECK(all_finite(grads.mean2d_abs));
  // The zero-scale Gaussians still render as the 0.3 px^2 dilation footprint.
  CHECK(out.radii[0] > 0);
  CHECK(out.radii[1] > 0);
}

TEST_CASE("raster: bad input is reported, not crashed on", "[splat][raster]") {
  GaussianModel model = one_gaussian({0.f, 0.f, 2.f}, {0.1f, 0.1f, 0.1f}, {1, 0, 0, 0});
  model.quats.pop_back();
  CHECK_THROWS_AS(render(model, hand_camera(), Pose{}, RenderSettings{}), InputError);
  Camera no_pixels;
  CHECK_THROWS_AS(render(one_gaussian({0, 0, 2}, {1, 1, 1}, {1, 0, 0, 0}), no_pixels, Pose{}, {}),
                  InputError);
}

TEST_CASE("raster: results are bitwise identical with 1 and 2 threads", "[splat][raster]") {
  const test::RasterScene scene = test::random_raster_scene(3000, 3, 8, 21, 160, 120);
  RenderSettings s;
  s.depth = s.normal = s.alpha = s.features = true;
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    RenderOutput out = render(scene.model, scene.camera, scene.pose, s);
    RenderGrads g;
    g.rgb = out.rgb;
    g.depth = out.depth;
    g.normal = out.normal;
    g.alpha = out.alpha;
    g.features.assign(out.features.begin(), out.features.end());
    ModelGrads grads;
    grads.reset(scene.model);
    render_backward(scene.model, scene.camera, scene.pose, s, out, g, grads);
    return std::pair{out, grads};
  };
  const auto [out1, grads1] = run(1);
  const auto [out2, grads2] = run(2);
  CHECK(out1.rgb == out2.rgb);
  CHECK(out1.depth == out2.depth);
  CHECK(out1.features == out2.features);
  CHECK(grads1.means == grads2.means);
  CHECK(grads1.log_scales == grads2.log_scales);
  CHECK(grads1.quats == grads2.quats);
  CHECK(grads1.opacity_logits == grads2.opacity_logits);
  CHECK(grads1.sh == grads2.sh);
  CHECK(grads1.features == grads2.features);
  CHECK(grads1.mean2d_abs == grads2.mean2d_abs);
  // The scene is not trivially empty.
  int visible = 0;
  for (int v : grads1.visible) visible += v;
  CHECK(visible > 1000);
}

namespace {

// Largest difference between the rendered red channel and accumulated alpha and the 3DGS rule
// written per pixel, in double: every Gaussian whose 3-sigma square touches the pixel's 16x16
// tile, front to back by (depth, index), alpha = min(0.99, o exp(.)), skipped below 1/255, stop
// before T < 1e-4. Also counts the pixels with reference T below 0.5 and below 1e-3.
struct ReferenceComparison {
  double max_diff = 0;
  int drawn = 0, saturated = 0;
};

ReferenceComparison compare_with_per_pixel_reference(const test::RasterScene& scene) {
  const int width = scene.camera.width, height = scene.camera.height;
  RenderSettings s;
  s.alpha = true;
  const RenderOutput out = render(scene.model, scene.camera, scene.pose, s);
  const ViewTransform view(scene.camera, scene.pose);
  struct Entry {
    ProjectedGaussian p;
    double opacity, colour;
    int index;
  };
  std::vector<Entry> visible;
  for (int i = 0; i < int(scene.model.size()); ++i) {
    Entry e;
    if (!project_gaussian(view, &scene.model.means[3 * i], &scene.model.log_scales[3 * i],
                          &scene.model.quats[4 * i], 0.01f, e.p))
      continue;
    e.opacity = 1.0 / (1.0 + std::exp(-double(scene.model.opacity_logits[i])));
    e.colour = std::max(0.0, 0.5 + 0.28209479177387814 * scene.model.sh[3 * i]);
    e.index = i;
    visible.push_back(e);
  }
  std::sort(visible.begin(), visible.end(), [](const Entry& a, const Entry& b) {
    return a.p.depth < b.p.depth || (a.p.depth == b.p.depth && a.index < b.index);
  });
  ReferenceComparison result;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double T = 1, red = 0;
      for (const Entry& e : visible) {
        const double r = e.p.radius, mx = e.p.mean2d.x(), my = e.p.mean2d.y();
        const int tx = x / 16, ty = y / 16;
        if (std::floor((mx + r) / 16) < tx || std::floor((mx - r) / 16) > tx ||
            std::floor((my + r) / 16) < ty || std::floor((my - r) / 16) > ty)
          continue;
        const double dx = mx - (x + 0.5), dy = my - (y + 0.5);
        const double power =
            -0.5 * (e.p.conic[0] * dx * dx + e.p.conic[2] * dy * dy) - e.p.conic[1] * dx * dy;
        const double alpha = std::min(0.99, e.opacity * std::exp(power));
        if (power > 0 || alpha < 1.0 / 255.0) continue;
        if (T * (1 - alpha) < 1e-4) break;
        red += e.colour * alpha * T;
        T *= 1 - alpha;
      }
      const size_t pix = size_t(y) * width + x;
      result.max_diff = std::max(result.max_diff, std::abs(red - out.rgb[pix * 3]));
      result.max_diff = std::max(result.max_diff, std::abs((1 - T) - out.alpha[pix]));
      result.drawn += T < 0.5;
      result.saturated += T < 1e-3;
    }
  return result;
}

}  // namespace

TEST_CASE("raster: the tightened pixel boxes give the 3DGS image", "[splat][raster]") {
  const ReferenceComparison c =
      compare_with_per_pixel_reference(test::random_raster_scene(150, 0, 0, 17, 80, 56));
  CHECK(c.drawn > 500);
  // Float against double, and contributions within rounding of the 1/255 threshold.
  CHECK(c.max_diff < 1e-5);
}

TEST_CASE("raster: Gaussians at the same depth are blended in index order", "[splat][raster]") {
  // Two depths only, every Gaussian tied with a third or two thirds of the others: the image
  // depends on how ties are broken, and the reference breaks them by index.
  test::RasterScene scene = test::random_raster_scene(150, 0, 0, 23, 80, 56);
  scene.pose.R.setIdentity();
  scene.pose.t.setZero();  // depth = the mean's z, exactly
  for (size_t i = 0; i < scene.model.size(); ++i) {
    float* mean = &scene.model.means[3 * i];
    const float z = i % 3 == 0 ? 2.5f : 3.f;
    mean[0] = 0.4f * z * (float(i % 17) / 8.f - 1.f);
    mean[1] = 0.3f * z * (float(i % 13) / 6.f - 1.f);
    mean[2] = z;
  }
  const ReferenceComparison c = compare_with_per_pixel_reference(scene);
  CHECK(c.drawn > 500);
  CHECK(c.max_diff < 1e-5);
}

TEST_CASE("raster: a slanted Gaussian's tile entries keep the rows it can blend in, no others",
          "[splat][raster]") {
  // A thin Gaussian along the image diagonal (rotated 45 degrees about the optical axis), long
  // enough that its pixel box is the whole 64 x 64 view: 16 tiles. Its line y = x passes 34 px
  // from the centre of the tiles (3, 0) and (0, 3), so their entries get no rows; in every tile,
  // every pixel where blend_row lets it blend lies in its entry's rows.
  Camera camera;
  camera.width = camera.height = 64;
  camera.fx = camera.fy = 64;
  camera.cx = camera.cy = 32;
  const float half = 0.3926991f;  // 22.5 degrees: a rotation of 45 degrees about z
  const GaussianModel m = one_gaussian({0.f, 0.f, 2.f}, {0.6f, 0.01f, 0.01f},
                                       {std::cos(half), 0.f, 0.f, std::sin(half)});
  const RenderOutput out = render(m, camera, Pose{}, RenderSettings{});
  const RasterState& s = *out.state;
  REQUIRE(s.tile_count() == 16);
  REQUIRE(s.tile_gaussians.size() == 16);  // in every tile's list
  int rows_kept = 0, pixels_blended = 0;
  for (int t = 0; t < 16; ++t) {
    const TileGaussian& e = s.tile_gaussians[s.tile_offsets[t]];
    const PixelRect tile = tile_pixels(s, t), rows = clip(e, tile);
    rows_kept += std::max(0, rows.y1 - rows.y0);
    if (t == 3 || t == 12) CHECK(rows.y1 <= rows.y0);
    for (int y = tile.y0; y < tile.y1; ++y) {
      float gaussian[kLanes], alpha[kLanes];
      blend_row(e, y, tile.x0, tile.x0 + kLanes, s.min_alpha, gaussian, alpha);
      for (int x = std::max<int>(e.x0, tile.x0); x < std::min<int>(e.x1, tile.x1); ++x)
        if (alpha[x - tile.x0] >= 0.f) {
          ++pixels_blended;
          CHECK(y >= rows.y0);
          CHECK(y < rows.y1);
        }
    }
  }
  CHECK(pixels_blended > 200);
  // The diagonal tiles keep their 16 rows, their neighbours some: far fewer than 16 x 16.
  CHECK(rows_kept >= 64);
  CHECK(rows_kept < 160);
}

TEST_CASE("raster: tiles where every pixel reaches T < 1e-4 stop early with the 3DGS image",
          "[splat][raster]") {
  // Large, nearly opaque Gaussians: nearly every pixel stops after a few of the hundreds of entries
  // of its tile, so the blending loop leaves most tiles early (a few corner pixels stay
  // uncovered).
  test::RasterScene scene = test::random_raster_scene(600, 0, 0, 23, 80, 56);
  for (float& o : scene.model.opacity_logits) o = 4.f;
  for (float& l : scene.model.log_scales) l += std::log(4.f);
  const ReferenceComparison c = compare_with_per_pixel_reference(scene);
  CHECK(c.saturated > 80 * 56 * 95 / 100);
  CHECK(c.max_diff < 1e-5);
}
