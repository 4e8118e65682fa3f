// Line-of-sight weights and footprints against hand-placed Gaussians in front of, on and
// behind an observed wall.
#include <cmath>

#include <tbb/global_control.h>

#include "nodes/splat/free_space.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

GaussianModel centres(const std::vector<Eigen::Vector3f>& xs) {
  GaussianModel m;
  m.resize(xs.size());
  for (size_t i = 0; i < xs.size(); ++i)
    for (int k = 0; k < 3; ++k) m.means[i * 3 + k] = xs[i][k];
  return m;
}

// The point of pixel (u, v) of `cam` (at the origin, looking down +z) at depth z.
Eigen::Vector3f at(const Camera& cam, double u, double v, double z) {
  return Eigen::Vector3f(float((u - cam.cx) / cam.fx * z), float((v - cam.cy) / cam.fy * z),
                         float(z));
}

// The model's rendered opacity summed over the view's pixels.
double summed_opacity(const GaussianModel& m, const Camera& cam, const Pose& pose) {
  RenderSettings alpha_only;
  alpha_only.rgb = false;
  alpha_only.alpha = true;
  double alpha = 0;
  for (float a : render(m, cam, pose, alpha_only).alpha) alpha += a;
  return alpha;
}

}  // namespace

TEST_CASE("line of sight: a Gaussian's weight splits by where each pixel observed its surface") {
  // The left half of the image observes a wall at 4 m, the right half an object at 1 m. Gaussian
  // 0 (3 m, straddling the two halves) is in front of the wall on the left and behind the object
  // on the right; Gaussian 1 lies on the wall, Gaussian 2 floats at 2 m in front of it.
  const Camera cam = test::centred_pinhole(80, 40, 60);
  const Pose pose;
  cv::Mat1f depth(cam.height, cam.width, 4.f);
  depth(cv::Rect(40, 0, 40, 40)) = 1.f;
  GaussianModel m =
      centres({at(cam, 40.0, 20.0, 3.0), at(cam, 12.0, 20.0, 4.0), at(cam, 25.0, 20.0, 2.0)});
  for (size_t i = 0; i < m.size(); ++i) {
    // Isotropic, 2-3 pixels across at its depth, opacity 0.8, apart from each other on screen.
    const double z = m.means[i * 3 + 2];
    for (int k = 0; k < 3; ++k) m.log_scales[i * 3 + k] = float(std::log(2.5 * z / cam.fx));
    m.opacity_logits[i] = float(std::log(0.8 / 0.2));
  }
  const std::vector<DepthObservation> views = {{&cam, &pose, depth}};
  const LineOfSightWeights w = line_of_sight_weights(m, views, 0.03);

  // Every weight is counted once: the sum over both parts is the rendered opacity.
  double total = 0;
  for (size_t i = 0; i < m.size(); ++i) total += w.free_space[i] + w.on_surface[i];
  CHECK(total == Approx(summed_opacity(m, cam, pose)).epsilon(1e-5));
  CHECK(w.unobserved == std::vector<double>(m.size(), 0.0));  // every pixel has a prior

  // Symmetric footprint across the boundary: half of it in free space.
  CHECK(w.free_space[0] / (w.free_space[0] + w.on_surface[0]) == Approx(0.5).margin(0.05));
  CHECK(w.free_space[1] == 0);
  CHECK(w.on_surface[1] > 1);
  CHECK(w.on_surface[2] == 0);
  CHECK(w.free_space[2] > 1);

  // Behind the observed surface: only 0's right half, which the object at 1 m hides.
  CHECK(w.behind[0] == Approx(w.on_surface[0]));
  CHECK(w.behind[1] == 0);
  CHECK(w.behind[2] == 0);
  CHECK(line_of_sight_prune_mask(w, 0.6) == std::vector<char>{0, 0, 1});
  CHECK(line_of_sight_prune_mask(w, 0, 0.4) == std::vector<char>{1, 0, 0});

  // The pruner in one round, by (in front, behind) fractions.
  FreeSpacePruneOptions o;
  o.tolerance = 0.03;
  const auto one_round = [&](double front, double behind) {
    FreeSpacePruneOptions x = o;
    x.line_of_sight = front;
    x.behind = behind;
    CHECK(x.active());
    return FreeSpacePruner(x).prune_mask(m, views);
  };
  CHECK(one_round(0.6, 0) == std::vector<char>{0, 0, 1});
  CHECK(one_round(0.4, 0) == std::vector<char>{1, 0, 1});
  CHECK(one_round(0, 0.4) == std::vector<char>{1, 0, 0});
  CHECK(one_round(0, 0.6) == std::vector<char>{0, 0, 0});
  CHECK(one_round(0.6, 0.6) == std::vector<char>{0, 0, 1});
  o.line_of_sight = 0.4;

  // Two rounds running: nothing in the first round; in the second the floater (2) and the
  // straddling Gaussian (0) go. A density round in between that keeps 2 but turns row 0 into a
  // new Gaussian (a split child, source -1) restarts 0's streak, and 1 (on the wall) never counts.
  o.line_of_sight_rounds = 2;
  FreeSpacePruner pruner(o);
  CHECK(pruner.prune_mask(m, views) == std::vector<char>{0, 0, 0});
  CHECK(pruner.prune_mask(m, views) == std::vector<char>{1, 0, 1});
  FreeSpacePruner remapped(o);
  CHECK(remapped.prune_mask(m, views) == std::vector<char>{0, 0, 0});
  remapped.remap({-1, 1, 2});
  CHECK(remapped.prune_mask(m, views) == std::vector<char>{0, 0, 1});
  CHECK(remapped.prune_mask(m, views) == std::vector<char>{1, 0, 1});
  // Rows reordered and one dropped: streaks follow their Gaussians (new row 0 is old 2).
  FreeSpacePruner reordered(o);
  reordered.prune_mask(m, views);
  reordered.remap({2, 1});
  GaussianModel kept = m.subset({2, 1});
  CHECK(reordered.prune_mask(kept, views) == std::vector<char>{1, 0});

  // The same sums, bit for bit, on one thread.
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const LineOfSightWeights serial = line_of_sight_weights(m, views, 0.03);
  CHECK(serial.free_space == w.free_space);
  CHECK(serial.on_surface == w.on_surface);
  CHECK(serial.behind == w.behind);
}

TEST_CASE(
    "line of sight: weight at pixels without a prior is unobserved, a hidden Gaussian has none") {
  // Three large opaque discs at 1.5-1.7 m in the middle of the view hide Gaussian 3 (4 m, right
  // behind them: the transmittance past them is under 3DGS's early-stop 1e-4); Gaussian 4 lies on
  // the wall at the left edge, where the prior has no depth; Gaussian 5 is outside the view.
  const Camera cam = test::centred_pinhole(80, 40, 60);
  const Pose pose;
  cv::Mat1f depth(cam.height, cam.width, 4.f);
  depth(cv::Rect(0, 0, 16, 40)) = 0.f;
  GaussianModel m = centres({at(cam, 40, 20, 1.5), at(cam, 40, 20, 1.6), at(cam, 40, 20, 1.7),
                             at(cam, 40, 20, 4.0), at(cam, 8, 20, 4.0), at(cam, -30, 20, 4.0)});
  for (size_t i = 0; i < m.size(); ++i) {
    const double z = m.means[i * 3 + 2], pixels = i < 3 ? 16.0 : i == 3 ? 1.0 : 2.0;
    for (int k = 0; k < 3; ++k) m.log_scales[i * 3 + k] = float(std::log(pixels * z / cam.fx));
    const double opacity = i < 3 ? 0.99 : 0.8;
    m.opacity_logits[i] = float(std::log(opacity / (1 - opacity)));
  }
  const std::vector<DepthObservation> views = {{&cam, &pose, depth}};
  const LineOfSightWeights w = line_of_sight_weights(m, views, 0.03);

  // The three parts sum to the rendered opacity: no weight is lost where the prior has a hole.
  double total = 0;
  for (size_t i = 0; i < m.size(); ++i)
    total += w.free_space[i] + w.on_surface[i] + w.unobserved[i];
  CHECK(total == Approx(summed_opacity(m, cam, pose)).epsilon(1e-5));
  CHECK(w.unobserved[4] > 1);
  CHECK(w.free_space[4] + w.on_surface[4] == 0);
  CHECK(w.free_space[0] > 10);  // the front disc, in front of the wall
  CHECK(w.unobserved[0] < w.free_space[0]);
  for (int hidden : {3, 5})
    CHECK(w.free_space[hidden] + w.on_surface[hidden] + w.unobserved[hidden] == 0);
}

TEST_CASE("footprint behind: a Gaussian hidden behind the observed surface is, whatever hides it") {
  // The left half of the image observes a wall at 4 m, the right half an object at 1 m. Gaussian
  // 0 (3 m) straddles the two halves: in front of the wall on the left, behind the object on the
  // right. Gaussian 1 lies on the wall, Gaussian 2 (3 m) behind the object, and Gaussian 3, a
  // large opaque disc at 0.5 m, hides Gaussian 1 from the camera.
  const Camera cam = test::centred_pinhole(80, 40, 60);
  const Pose pose;
  cv::Mat1f depth(cam.height, cam.width, 4.f);
  depth(cv::Rect(40, 0, 40, 40)) = 1.f;
  GaussianModel m = centres({at(cam, 40.0, 20.0, 3.0), at(cam, 12.0, 20.0, 4.0),
                             at(cam, 60.0, 20.0, 3.0), at(cam, 12.0, 20.0, 0.5)});
  for (size_t i = 0; i < m.size(); ++i) {
    const double z = m.means[i * 3 + 2], pixels = i == 3 ? 8.0 : 2.5;
    for (int k = 0; k < 3; ++k) m.log_scales[i * 3 + k] = float(std::log(pixels * z / cam.fx));
    const double opacity = i == 3 ? 0.99 : 0.8;
    m.opacity_logits[i] = float(std::log(opacity / (1 - opacity)));
  }
  const std::vector<DepthObservation> views = {{&cam, &pose, depth}};
  const FootprintDepth f = footprint_behind(m, views, 0.03);

  // The footprint is the Gaussian's own opacity summed over its pixels, with nothing in front:
  // Gaussian 1 draws little weight behind the disc, but its footprint is what it covers alone.
  CHECK(line_of_sight_weights(m, views, 0.03).on_surface[1] < 0.1 * f.observed[1]);
  CHECK(f.observed[1] == Approx(summed_opacity(m.subset({1}), cam, pose)).epsilon(1e-5));
  CHECK(f.behind[1] == 0);
  CHECK(f.behind[3] == 0);
  CHECK(f.behind[2] == Approx(f.observed[2]));
  CHECK(f.observed[2] > 1);
  CHECK(f.behind[0] / f.observed[0] == Approx(0.5).margin(0.05));

  // The pruner's rule, in one round.
  const auto one_round = [&](double hidden) {
    FreeSpacePruneOptions o;
    o.tolerance = 0.03;
    o.hidden = hidden;
    CHECK(o.active());
    return FreeSpacePruner(o).prune_mask(m, views);
  };
  CHECK(one_round(0.8) == std::vector<char>{0, 0, 1, 0});
  CHECK(one_round(0.4) == std::vector<char>{1, 0, 1, 0});

  // Over several views the footprints add up: a view that sees Gaussian 2 on its surface (its
  // prior at 3 m everywhere) halves its fraction behind.
  cv::Mat1f at_three(cam.height, cam.width, 3.f);
  const std::vector<DepthObservation> two = {{&cam, &pose, depth}, {&cam, &pose, at_three}};
  const FootprintDepth f2 = footprint_behind(m, two, 0.03);
  CHECK(f2.behind[2] / f2.observed[2] == Approx(0.5));

  // The same sums, bit for bit, on one thread.
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const FootprintDepth serial = footprint_behind(m, views, 0.03);
  CHECK(serial.observed == f.observed);
  CHECK(serial.behind == f.behind);
}
