// Initialisation from depth and points, and one density-control round, on hand-made cases.
#include <cmath>

#include <Eigen/Geometry>

#include "nodes/splat/density_control.hpp"
#include "nodes/splat/initialise.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

constexpr double kSH0 = 0.28209479177387814;

// One view looking down +z at the plane z = 2 (identity pose), 64x48 pixels, f = 50: every
// pixel's footprint is 2 / 50 = 0.04 m.
Capture plane_capture() {
  Capture c;
  c.name = "plane";
  View v;
  v.name = "cam_00";
  v.camera = test::centred_pinhole(64, 48, 50);
  v.rgb = ImageSource::in_memory(cv::Mat(48, 64, CV_8UC3, cv::Scalar(200, 100, 50)));
  v.depth = ImageSource::in_memory(cv::Mat(48, 64, CV_32FC1, cv::Scalar(2.0)));
  c.views.push_back(v);
  return c;
}

}  // namespace

TEST_CASE("depth initialisation voxelises a plane at the pixel footprint") {
  const Capture capture = plane_capture();
  InitialiseOptions options;
  options.pixel_stride = 1;
  // Voxel 3.7 x 0.04 = 0.148 m. Pixel centres x = 0.04 (u - 31.5); Open3D bins from the minimum
  // minus half a voxel, so bin(u) = floor(0.5 + 0.04 u / 0.148) (never on a boundary): u = 0..63
  // gives bins 0..17 (18) and v = 0..47 gives 0..13 (14): 252 Gaussians.
  options.footprint_factor = 3.7;
  options.scale_factor = 1;
  options.normal_thickness = 1;  // isotropic, as 3DGS
  const GaussianModel m = initialise_gaussians(capture, options);
  REQUIRE(m.size() == 252);
  std::vector<float> scales;
  for (size_t i = 0; i < m.size(); ++i) {
    CHECK(m.means[i * 3 + 2] == Approx(2.0f));
    CHECK(m.log_scales[i * 3] == m.log_scales[i * 3 + 2]);  // isotropic
    scales.push_back(std::exp(m.log_scales[i * 3]));
  }
  // Neighbouring voxel centroids are ~one voxel apart: the 3-NN RMS distance is close to 0.148.
  std::nth_element(scales.begin(), scales.begin() + scales.size() / 2, scales.end());
  CHECK(scales[scales.size() / 2] == Approx(0.148).epsilon(0.12));
  CHECK(m.sh[0] == Approx((200 / 255.0 - 0.5) / kSH0).epsilon(1e-5));
  CHECK(m.sh[2] == Approx((50 / 255.0 - 0.5) / kSH0).epsilon(1e-5));
  CHECK(m.opacity_logits[0] == Approx(std::log(0.1 / 0.9)));
  CHECK(m.quats[0] == 1.f);
}

TEST_CASE("depth initialisation turns Gaussians into discs along the depth prior's normal") {
  const Capture capture = plane_capture();
  InitialiseOptions options;
  options.pixel_stride = 1;
  options.footprint_factor = 3.7;
  options.normal_thickness = 0.25;
  const GaussianModel m = initialise_gaussians(capture, options);
  REQUIRE(m.size() == 252);
  // The border pixels have no prior normal, so the 18 x 14 voxels of the image's outer ring (mostly
  // border pixels) stay isotropic; the 16 x 12 inner ones become discs.
  size_t discs = 0;
  for (size_t i = 0; i < m.size(); ++i) {
    const float* s = &m.log_scales[i * 3];
    const float* q = &m.quats[i * 4];
    CHECK(s[0] == s[1]);
    if (s[2] == s[0]) {
      CHECK(q[0] == 1.f);
      continue;
    }
    ++discs;
    CHECK(s[2] == Approx(s[0] + std::log(0.25f)).margin(1e-5));
    // The plane z = 2 faces the camera at the origin: the prior's normal is (0, 0, -1), so the
    // rotated z axis (the shortest, the rasterizer's normal) must be -z.
    const Eigen::Vector3f axis =
        Eigen::Quaternionf(q[0], q[1], q[2], q[3]) * Eigen::Vector3f::UnitZ();
    CHECK(axis.z() == Approx(-1.f).margin(1e-5));
  }
  CHECK(discs >= 16 * 12);
}

TEST_CASE("points initialisation takes scales from the 3 nearest neighbours") {
  Capture capture = plane_capture();
  capture.views[0].depth = ImageSource();
  for (auto [x, y] : {std::pair{0, 0}, {1, 0}, {0, 1}, {1, 1}}) {
    capture.points.xyz.emplace_back(x, y, 3);
    capture.points.rgb.emplace_back(255, 0, 0);
  }
  const GaussianModel m = initialise_gaussians(capture, InitialiseOptions{});
  REQUIRE(m.size() == 4);
  // Each corner of the unit square: neighbours at 1, 1, sqrt(2): sqrt((1 + 1 + 2) / 3), times
  // the default scale factor 0.5.
  for (size_t i = 0; i < 4; ++i)
    CHECK(std::exp(m.log_scales[i * 3 + 1]) == Approx(0.5 * std::sqrt(4.0 / 3)));
  CHECK(m.sh[0] == Approx(0.5 / kSH0));

  // Without points or depth, auto falls back to random points, which need two training views.
  Capture empty = plane_capture();
  empty.views[0].depth = ImageSource();
  REQUIRE(empty.train_views().size() == 1u);
  CHECK_THROWS_WITH(initialise_gaussians(empty, InitialiseOptions{}),
                    Catch::Contains("neither sparse points nor a depth prior") &&
                        Catch::Contains("two training views"));
}

TEST_CASE("the initialisation source: auto takes the depth prior, points the sparse points") {
  Capture capture = plane_capture();
  for (auto [x, y] : {std::pair{0, 0}, {1, 0}, {0, 1}, {1, 1}}) {
    capture.points.xyz.emplace_back(x, y, 3);
    capture.points.rgb.emplace_back(255, 0, 0);
  }
  InitialiseOptions options;
  options.footprint_factor = 3.7;
  options.pixel_stride = 1;
  CHECK(initialise_gaussians(capture, options).size() == 252);  // as the voxel test above
  options.source = InitSource::Points;
  const GaussianModel m = initialise_gaussians(capture, options);
  REQUIRE(m.size() == 4);
  for (size_t i = 0; i < 4; ++i) CHECK(m.means[i * 3 + 2] == 3.f);
  CHECK(parse_enum("depth", init_source_names(), "init") == InitSource::Depth);
  CHECK_THROWS_AS(parse_enum("mvs", init_source_names(), "init"), std::invalid_argument);
}

TEST_CASE("density control clones small, splits large, prunes transparent and huge Gaussians") {
  GaussianModel m;
  m.resize(5);
  const double extent = 10;  // clone when max scale <= 0.1, prune when > 1
  const float logit_opaque = 2.f, logit_clear = -8.f;  // sigmoid(-8) = 3.4e-4 < 0.005
  const float scales[5] = {0.05f, 0.5f, 0.05f, 2.f, 0.05f};
  const float logits[5] = {logit_opaque, logit_opaque, logit_clear, logit_opaque, logit_opaque};
  for (int i = 0; i < 5; ++i) {
    m.means[i * 3] = static_cast<float>(i);
    for (int k = 0; k < 3; ++k) m.log_scales[i * 3 + k] = std::log(scales[i]);
    m.opacity_logits[i] = logits[i];
  }
  DensityStats stats;
  // Gaussians 0 and 1 have mean gradients 3e-4 and 5e-4 (> 2e-4); 2 and 3 too but are pruned;
  // Gaussian 4 is below the threshold (1e-4 over two views).
  stats.add({3e-4f, 5e-4f, 9e-4f, 9e-4f, 1e-4f}, {1, 1, 1, 1, 1});
  stats.add({0, 0, 0, 0, 1e-4f}, {0, 0, 0, 0, 1});
  DensityControlOptions options;
  GaussianModel grown = m;
  const DensityChange change = densify_and_prune(grown, stats, options, extent, 7);
  CHECK(change.refused == 0);
  CHECK(change.pruned == 2);
  CHECK(change.cloned == 1);
  CHECK(change.split == 1);
  // Kept: 0, 4 (1 is replaced by its children); then the clone; then 2 children.
  CHECK(change.source == std::vector<int>{0, 4, -1, -1, -1});
  REQUIRE(grown.size() == 5);
  CHECK(grown.means[2 * 3] == 0.f);  // the clone sits on its parent
  for (int child : {3, 4}) {
    CHECK(std::exp(grown.log_scales[child * 3]) == Approx(0.5 / 1.6));
    CHECK(std::abs(grown.means[child * 3] - 1.f) < 5 * 0.5f);  // sampled around the parent
    CHECK(grown.means[child * 3 + 1] != 0.f);
  }
  // Same seed, same children; the budget stops growth at the largest gradient first.
  GaussianModel again = m;
  densify_and_prune(again, stats, options, extent, 7);
  CHECK(again.means == grown.means);
  options.max_gaussians = 4;  // 3 kept + 1: only the split (largest gradient, costs 1) fits
  GaussianModel capped = m;
  const DensityChange limited = densify_and_prune(capped, stats, options, extent, 7);
  CHECK(limited.split == 1);
  CHECK(limited.cloned == 0);
  CHECK(limited.refused == 1);  // the clone candidate
  CHECK(capped.size() == 4);

  // Pruning only (no statistics, as between rounds): the marked Gaussian 0 goes with the two
  // transparent/oversized ones, nothing grows, and the statistics follow the kept rows.
  GaussianModel pruned = m;
  const DensityChange only = densify_and_prune(pruned, DensityStats{}, DensityControlOptions{},
                                               extent, 7, {1, 0, 0, 0, 0});
  CHECK(only.source == std::vector<int>{1, 4});
  CHECK(only.cloned + only.split == 0);
  DensityStats followed = stats;
  followed.remap(only.source);
  CHECK(followed.grad_sum == std::vector<double>{stats.grad_sum[1], stats.grad_sum[4]});
  CHECK(followed.visible == std::vector<int>{1, 2});
}

TEST_CASE("density steps follow the compressed schedule") {
  DensityControlOptions o;  // every 50 from 100 to 60% of the run
  std::vector<int> steps;
  for (int s = 0; s < 500; ++s)
    if (is_density_step(o, s, 500)) steps.push_back(s);
  CHECK(steps == std::vector<int>{100, 150, 200, 250, 300});
}

TEST_CASE("initial scale: RMS (3DGS) or mean (OpenSplat) distance to the 3 nearest points") {
  // The origin's neighbours lie at 1, 2 and 2: RMS sqrt(9 / 3) = sqrt(3), mean 5 / 3.
  ColouredPoints points;
  points.xyz = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 2}};
  points.rgb.assign(4, Eigen::Vector3d(0.5, 0.5, 0.5));
  InitialiseOptions options;
  options.scale_factor = 0.5;
  const GaussianModel rms = gaussians_from_points(points, 0, options);
  CHECK(std::exp(rms.log_scales[0]) == Approx(0.5 * std::sqrt(3.0)).epsilon(1e-6));
  options.scale_distance = NeighbourDistance::Mean;
  options.scale_factor = 1;
  const GaussianModel mean = gaussians_from_points(points, 0, options);
  CHECK(std::exp(mean.log_scales[0]) == Approx(5.0 / 3).epsilon(1e-6));
  CHECK(mean.log_scales[0] == mean.log_scales[2]);  // no normals: isotropic
}

TEST_CASE("the reconstruction's extent follows the scene, not only the cameras' spread") {
  // Identity-rotation cameras at x = -0.1, 0, 0.1 (world -> camera t = -centre): 3DGS's camera
  // extent is 1.1 x 0.1 = 0.11.
  Capture c;
  for (const double x : {-0.1, 0.0, 0.1}) {
    View v;
    v.name = "cam_" + std::to_string(c.views.size());
    v.pose.t = Eigen::Vector3d(-x, 0, 0);
    c.views.push_back(v);
  }
  CHECK(scene_extent(c) == Approx(0.11));
  // A room filmed from inside: Gaussians 1, 2 and 3 m from the cameras' centroid. The median
  // distance, 2 m, sets the scale (a prune at 0.1 x extent then takes Gaussians over 0.2 m,
  // not over 1.1 cm).
  const std::vector<float> room = {0, 0, 1, 0, 2, 0, 3, 0, 0};
  CHECK(reconstruction_extent(c, room) == Approx(2.0));
  // An object in the middle of cameras spread wider keeps the cameras' extent.
  const std::vector<float> object = {0, 0, 0.01f, 0, 0.02f, 0, 0.03f, 0, 0};
  CHECK(reconstruction_extent(c, object) == Approx(0.11));
}
