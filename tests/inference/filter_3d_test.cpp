// 3D post-processing on hand-built point sets whose answers follow from the definitions.
#include "nodes/inference/filter_3d.hpp"
#include "nodes/inference/growth_exclusion.hpp"
#include "nodes/inference/mask_silhouette.hpp"

#include <random>

#include <tbb/global_control.h>

#include "tests/test_support.hpp"

using namespace gslift;

namespace {

struct Points {
  std::vector<float> means;
  std::vector<int32_t> ids;
  size_t add(double x, double y, double z, int32_t id) {
    // Three push_backs, not insert of a braced list: g++ 12 reports a false
    // -Wstringop-overflow inside std::vector::insert for the latter.
    means.push_back(float(x));
    means.push_back(float(y));
    means.push_back(float(z));
    ids.push_back(id);
    return ids.size() - 1;
  }
  // An nx x ny grid with spacing 1 in the z = 0 plane, starting at (x0, y0).
  void grid(double x0, double y0, int nx, int ny, int32_t id) {
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j) add(x0 + i, y0 + j, 0, id);
  }
};

Filter3dOptions only(bool statistical, bool components, bool grow) {
  Filter3dOptions o;
  o.statistical = statistical;
  o.components = components;
  o.grow = grow;
  return o;
}

}  // namespace

TEST_CASE("filter_3d: the statistical filter removes a far outlier and nothing else",
          "[inference][filter_3d]") {
  Points p;
  p.grid(0, 0, 5, 5, 0);
  const size_t outlier = p.add(20, 0, 0, 0);
  // k = round(sqrt(26)) = 5. Grid points' mean 5-NN distance is at most (1 + 1 + 1.41 + 2 + 2)/5
  // = 1.48 (a corner); the outlier's is 16.2; mu = 1.76, sigma = 2.89: only it exceeds
  // mu + sigma.
  const Filter3dResult r = filter_instances_3d(p.means, p.ids, only(true, false, false));
  CHECK(r.outliers == 1);
  CHECK(r.instance_ids[outlier] == -1);
  for (size_t g = 0; g < 25; ++g) CHECK(r.instance_ids[g] == 0);
}

TEST_CASE("filter_3d: a small separate component is dropped, a large one is kept",
          "[inference][filter_3d]") {
  SECTION("4 of 29 Gaussians (14% < 20%) in a second piece: dropped") {
    Points p;
    p.grid(0, 0, 5, 5, 3);
    p.grid(10, 0, 2, 2, 3);
    const Filter3dResult r = filter_instances_3d(p.means, p.ids, only(false, true, false));
    CHECK(r.component_dropped == 4);
    for (size_t g = 0; g < 25; ++g) CHECK(r.instance_ids[g] == 3);
    for (size_t g = 25; g < 29; ++g) CHECK(r.instance_ids[g] == -1);
  }
  SECTION("9 of 34 Gaussians (26% >= 20%) in a second piece: kept") {
    Points p;
    p.grid(0, 0, 5, 5, 3);
    p.grid(10, 0, 3, 3, 3);
    const Filter3dResult r = filter_instances_3d(p.means, p.ids, only(false, true, false));
    CHECK(r.component_dropped == 0);
    for (const int32_t id : r.instance_ids) CHECK(id == 3);
  }
  SECTION("pieces joined by a chain of points no farther apart than the largest NN distance") {
    Points p;
    p.grid(0, 0, 5, 5, 1);
    // A bridge of points 1.0 apart from (5, 0) to (9, 0), then a 2x2 piece at x = 10: one
    // component, since the link radius is the largest nearest-neighbour distance, 1.
    for (int x = 5; x < 10; ++x) p.add(x, 0, 0, 1);
    p.grid(10, 0, 2, 2, 1);
    const Filter3dResult r = filter_instances_3d(p.means, p.ids, only(false, true, false));
    CHECK(r.component_dropped == 0);
  }
}

TEST_CASE("filter_3d: growth takes unassigned Gaussians within the largest NN distance",
          "[inference][filter_3d]") {
  Points p;
  p.grid(0, 0, 5, 5, 0);                      // largest nearest-neighbour distance: 1
  const size_t near = p.add(5, 0, 0, -1);     // 1.0 from (4, 0): joins
  const size_t far = p.add(0, -1.25, 0, -1);  // 1.25 from (0, 0): stays out
  const size_t above = p.add(2, 2, 0.9, -1);  // 0.9 above (2, 2): joins
  const Filter3dResult r = filter_instances_3d(p.means, p.ids, only(false, false, true));
  CHECK(r.grown == 2);
  CHECK(r.instance_ids[near] == 0);
  CHECK(r.instance_ids[above] == 0);
  CHECK(r.instance_ids[far] == -1);
}

TEST_CASE("filter_3d: a removed Gaussian becomes unassigned, never another instance's",
          "[inference][filter_3d]") {
  Points p;
  p.grid(0, 0, 5, 5, 0);
  p.grid(30, 0, 5, 5, 1);
  // An outlier of instance 0 lying on instance 1's grid, well within its growth radius.
  const size_t stray = p.add(32, 2, 0.5, 0);
  const Filter3dResult r = filter_instances_3d(p.means, p.ids, Filter3dOptions{});
  // Instance 1 is a clean grid, and still the one-sided mu + sigma cut takes its 4 corners (mean
  // 5-NN distance 1.48 against mu 1.19, sigma 0.13); growth restores them (1 from the kept set).
  // The stray is instance 0's outlier: instance 1 may not take it.
  CHECK(r.outliers == 5);
  CHECK(r.restored == 4);
  CHECK(r.grown == 0);
  CHECK(r.instance_ids[stray] == -1);
  for (size_t g = 0; g < 50; ++g) CHECK(r.instance_ids[g] == (g < 25 ? 0 : 1));
}

TEST_CASE("filter_3d: small instances are left alone, bad options and sizes are refused",
          "[inference][filter_3d]") {
  Points p;
  p.add(0, 0, 0, 2);
  p.add(100, 0, 0, 2);
  const Filter3dResult r = filter_instances_3d(p.means, p.ids, Filter3dOptions{});
  CHECK(r.instance_ids == p.ids);
  Filter3dOptions bad;
  bad.min_component_fraction = 2;
  CHECK_THROWS_WITH(filter_instances_3d(p.means, p.ids, bad),
                    Catch::Contains("min_component_fraction"));
  p.ids.pop_back();
  CHECK_THROWS_AS(filter_instances_3d(p.means, p.ids, Filter3dOptions{}), std::invalid_argument);
}

TEST_CASE("filter_3d: the same answer at 1, 2 and 4 threads", "[inference][filter_3d]") {
  // Issue 33: graphs/saga.yaml's masks differed between 1 and 2 threads. Three noisy instances
  // that touch, grid points at equal distances (ties in every neighbour search), duplicates and
  // unassigned Gaussians among them.
  Points p;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.6);
  for (int32_t id = 0; id < 3; ++id)
    for (int i = 0; i < 400; ++i) p.add(3 * id + noise(rng), noise(rng), noise(rng), id);
  p.grid(-2, -2, 12, 5, 1);
  p.grid(-2, -2, 12, 5, -1);  // the same places, unassigned
  for (int i = 0; i < 300; ++i) p.add(8 * noise(rng), 3 * noise(rng), noise(rng), -1);
  const auto run = [&](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    return filter_instances_3d(p.means, p.ids, Filter3dOptions{});
  };
  const Filter3dResult one = run(1);
  // Every step had something to do, so each is compared.
  CHECK(one.outliers > 0);
  CHECK(one.grown > 0);
  CHECK(one.restored > 0);
  for (const int threads : {2, 4}) {
    INFO(threads << " threads");
    const Filter3dResult r = run(threads);
    CHECK(r.instance_ids == one.instance_ids);
    CHECK(r.outliers == one.outliers);
    CHECK(r.component_dropped == one.component_dropped);
    CHECK(r.grown == one.grown);
    CHECK(r.restored == one.restored);
  }
}

TEST_CASE("filter_3d: growth searches the kept centres themselves", "[inference][filter_3d]") {
  // Issue 33: the growth search ran on a freed copy of the kept centres (Open3D 0.16's tree keeps
  // a view of the matrix it is given, not its own copy), so what it found depended on who reused
  // the memory: growth changed with the thread count. Before the fix the Gaussian that only the
  // first kept centre reaches was not grown.
  Points p;
  p.grid(100, 100, 100, 90, 0);                    // the first kept Gaussian is (100, 100, 0)
  const size_t edge = p.add(99.5, 100, 0, -1);     // 0.5 from it, > 1 from every other one
  const size_t corner = p.add(199.4, 189, 0, -1);  // 0.4 from the last one, (199, 189, 0)
  const Filter3dResult r = filter_instances_3d(p.means, p.ids, only(false, false, true));
  CHECK(r.instance_ids[edge] == 0);
  CHECK(r.instance_ids[corner] == 0);
  CHECK(r.grown == 2);
}

TEST_CASE("filter_3d: growth that would turn a selection into the scene is refused",
          "[inference][filter_3d]") {
  // Issue 28: a sparse selection (a 5 x 5 grid at spacing 2: growth radius 2) lying under a dense
  // unassigned surface (11 x 11 at spacing 1, 1 above it, every point at most sqrt(3) from a
  // selected one): one ball query takes the whole surface, 25 -> 146 Gaussians (5.8x).
  Points p;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) p.add(2 * i, 2 * j, 0, 0);
  for (int i = -1; i <= 9; ++i)
    for (int j = -1; j <= 9; ++j) p.add(i, j, 1, -1);
  SECTION("unbounded (the defaults), it floods") {
    const Filter3dOptions o = only(false, false, true);
    const Filter3dResult r = filter_instances_3d(p.means, p.ids, o);
    CHECK(r.grown == 121);
    CHECK(r.refused == 0);
    REQUIRE(r.growth.size() == 1);
    CHECK(r.growth[0].after == 146);
  }
  SECTION("by max_growth_ratio 3, it is refused and the un-grown selection kept") {
    Filter3dOptions o = only(false, false, true);
    o.max_growth_ratio = 3;
    const Filter3dResult r = filter_instances_3d(p.means, p.ids, o);
    CHECK(r.grown == 0);
    CHECK(r.refused == 1);
    REQUIRE(r.growth.size() == 1);
    CHECK(r.growth[0].id == 0);
    CHECK(r.growth[0].kept == 25);
    CHECK(r.growth[0].would_be == 146);
    CHECK(r.growth[0].after == 25);
    CHECK(r.growth[0].refused);
    CHECK(r.instance_ids == p.ids);
  }
  SECTION("the scene-fraction bound alone refuses it too (146 of 146 Gaussians)") {
    // (off by default: docs/saga.md)
    Filter3dOptions o = only(false, false, true);
    o.max_growth_ratio = 0;
    o.max_scene_fraction = 0.99;
    CHECK(filter_instances_3d(p.means, p.ids, o).refused == 1);
  }
}

TEST_CASE("filter_3d: growth that fills an object's edge passes the bounds",
          "[inference][filter_3d]") {
  // A 5 x 5 grid (radius 1) with its next row unassigned (5 Gaussians 1 away: 25 -> 30, 1.2x)
  // in a scene of 200 more Gaussians far away (30 of 230: 13%).
  Points p;
  p.grid(0, 0, 5, 5, 0);
  p.grid(5, 0, 1, 5, -1);
  p.grid(100, 100, 20, 10, -1);
  Filter3dOptions o = only(false, false, true);
  o.max_growth_ratio = 3;
  o.max_scene_fraction = 0.5;
  const Filter3dResult r = filter_instances_3d(p.means, p.ids, o);
  CHECK(r.grown == 5);
  CHECK(r.refused == 0);
  REQUIRE(r.growth.size() == 1);
  CHECK(r.growth[0].kept == 25);
  CHECK(r.growth[0].after == 30);
  CHECK_FALSE(r.growth[0].refused);
}

TEST_CASE("filter_3d: growth_box_margin keeps growth inside the selection's widened box",
          "[inference][filter_3d]") {
  // A 5 x 5 grid (box [0, 4]^2, radius 1) and unassigned Gaussians 1 past its edge: x = 5 is
  // outside the box widened by 5% (4.2) and inside it widened by 30% (5.2).
  Points p;
  p.grid(0, 0, 5, 5, 0);
  p.grid(5, 0, 1, 5, -1);
  const size_t above = p.add(2, 2, 0.9, -1);  // z = 0.9 against a flat box: widened by 0
  Filter3dOptions o = only(false, false, true);
  o.growth_box_margin = 0.05;
  Filter3dResult r = filter_instances_3d(p.means, p.ids, o);
  CHECK(r.grown == 0);
  CHECK(r.instance_ids[above] == -1);
  o.growth_box_margin = 0.3;
  r = filter_instances_3d(p.means, p.ids, o);
  CHECK(r.grown == 5);
}

TEST_CASE("filter_3d: growth stops at a feature edge when growth_min_similarity is set",
          "[inference][filter_3d]") {
  // A selected 5 x 5 grid (features along e0, one at 30 degrees to it) and an unassigned column
  // beside it at x = 5, within the growth radius 1. The column's upper half carries the
  // instance's feature direction (with a small tilt), its lower half another object's (e1).
  Points p;
  p.grid(0, 0, 5, 5, 0);
  std::vector<float> features;
  for (size_t g = 0; g < 25; ++g) {
    const bool tilted = g == 12;  // cos 30 = 0.866: the prototype is still close to e0
    features.push_back(tilted ? 0.866f : 1.f);
    features.push_back(tilted ? 0.5f : 0.f);
  }
  std::vector<size_t> same, other;
  for (int y = 0; y < 5; ++y) {
    const size_t g = p.add(5, y, 0, -1);
    if (y >= 3) {
      same.push_back(g);
      features.push_back(0.95f);  // cos to e0 = 0.95
      features.push_back(0.31f);
    } else {
      other.push_back(g);
      features.push_back(0.f);  // e1, unnormalised: the norm must not matter
      features.push_back(2.f);
    }
  }
  Filter3dOptions o = only(false, false, true);
  SECTION("without the check, the ball query takes the whole column") {
    const Filter3dResult r = filter_instances_3d(p.means, p.ids, o);
    CHECK(r.grown == 5);
  }
  SECTION("with it, only the Gaussians whose feature matches join") {
    o.growth_min_similarity = 0.9;
    // Prototype: (24 e0 + (0.866, 0.5)) / |.| = (0.9998, 0.0201); the matching Gaussians'
    // cosine to it is (0.95 x 0.9998 + 0.31 x 0.0201) / |(0.95, 0.31)| = 0.957 >= 0.9; e1's 0.0201.
    const Filter3dResult r = filter_instances_3d(p.means, p.ids, o, features, 2);
    CHECK(r.grown == 2);
    for (const size_t g : same) CHECK(r.instance_ids[g] == 0);
    for (const size_t g : other) CHECK(r.instance_ids[g] == -1);
    o.growth_min_similarity = 0.96;  // just above the matching Gaussians' 0.957
    CHECK(filter_instances_3d(p.means, p.ids, o, features, 2).grown == 0);
  }
  SECTION("the check without features is an error, not a silent ball query") {
    o.growth_min_similarity = 0.9;
    CHECK_THROWS_WITH(filter_instances_3d(p.means, p.ids, o),
                      Catch::Matchers::Contains("growth_min_similarity needs the Gaussians'"));
  }
}

TEST_CASE("filter_3d: an instance does not grow into Gaussians excluded from it",
          "[inference][filter_3d]") {
  // Three unassigned Gaussians within the growth radius (1) of a 5 x 5 grid: one excluded from
  // instance 0, and the exclusion of another instance must not matter.
  Points p;
  p.grid(0, 0, 5, 5, 0);
  const size_t left = p.add(-1, 2, 0, -1), right = p.add(5, 2, 0, -1), top = p.add(2, 5, 0, -1);
  GrowthExclusion excluded;
  excluded[0].assign(p.ids.size(), 0);
  excluded[0][right] = 1;
  excluded[7].assign(p.ids.size(), 1);
  const Filter3dResult r =
      filter_instances_3d(p.means, p.ids, only(false, false, true), {}, 0, excluded);
  CHECK(r.grown == 2);
  CHECK(r.excluded == 1);
  CHECK(r.instance_ids[left] == 0);
  CHECK(r.instance_ids[top] == 0);
  CHECK(r.instance_ids[right] == -1);
  excluded[0].pop_back();
  CHECK_THROWS_WITH(
      filter_instances_3d(p.means, p.ids, only(false, false, true), {}, 0, excluded),
      Catch::Matchers::Contains("instance 0's exclusion has 27 flags for 28 Gaussians"));
}

namespace {

// A 10 x 8 pinhole at the origin looking down +z, f = 10, principal point (5, 4): a centre
// (x, y, z) lands on pixel (10 x / z + 5, 10 y / z + 4).
View pinhole_view() {
  View view;
  view.name = "v0";
  view.camera.width = 10;
  view.camera.height = 8;
  view.camera.fx = view.camera.fy = 10;
  view.camera.cx = 5;
  view.camera.cy = 4;
  return view;
}

// The mask of pinhole_view's columns 0-4.
cv::Mat1b left_columns_mask() {
  cv::Mat1b mask(8, 10, uchar(0));
  mask.colRange(0, 5).setTo(255);
  return mask;
}

}  // namespace

TEST_CASE("mask_silhouette: Gaussians projecting outside a mask are ruled out, unseen ones not",
          "[inference][filter_3d]") {
  const View view = pinhole_view();
  const cv::Mat1b mask = left_columns_mask();
  const std::vector<float> means = {
      -0.2f,  0, 1,   // pixel (3, 4): inside the mask
      0.2f,   0, 1,   // pixel (7, 4): outside, ruled out
      0.4f,   0, 4,   // pixel (6, 4), 4 deep: outside, ruled out
      0.2f,   0, -1,  // behind the camera: not seen, kept
      2.f,    0, 1,   // pixel (25, 4): outside the frame, kept
      -0.05f, 0, 1,   // pixel (4.5, 4): column 4, inside
  };
  CHECK(centres_outside_mask(means, view, mask) == std::vector<char>{0, 1, 1, 0, 0, 0});
  CHECK_THROWS_WITH(centres_outside_mask(means, view, cv::Mat1b(8, 9, uchar(0))),
                    Catch::Matchers::Contains("mask of view 'v0' is 9x8, the view 10x8"));
}

TEST_CASE("growth exclusion: a mask's silhouette and the vote's outside Gaussians, per prompt",
          "[inference][filter_3d]") {
  Capture capture;
  capture.views = {pinhole_view()};
  // Gaussian 0 inside the mask (pixel (3, 4)), 1 outside it (pixel (7, 4)), 2 behind the camera.
  const std::vector<float> means = {-0.2f, 0, 1, 0.2f, 0, 1, 0.2f, 0, -1};
  PromptSet prompts;
  prompts.prompts = {{"masked", PromptKind::Mask, "v0", {}, {}, left_columns_mask()},
                     {"clicked", PromptKind::Point, "v0", {{3, 4}}, {}, {}}};
  // Without votes only the mask rules out, and the click rules out nothing.
  GrowthExclusion ex = prompt_growth_exclusion(means, capture, prompts, 0.9);
  CHECK(ex.size() == 1);
  CHECK(ex.at(0) == std::vector<char>{0, 1, 0});
  // Votes: below -0.9 rules out (Gaussian 2 for the mask prompt: seen only outside; Gaussian 0
  // for the click), -0.9 itself and an unseen 0 do not.
  prompts.vote_balance = {{0.5f, 0.f, -0.95f}, {-1.f, -0.9f, 0.f}};
  ex = prompt_growth_exclusion(means, capture, prompts, 0.9);
  CHECK(ex.at(0) == std::vector<char>{0, 1, 1});
  CHECK(ex.at(1) == std::vector<char>{1, 0, 0});
  // outside_vote 1: the vote rules nothing out; 0: every Gaussian seen more outside than inside.
  CHECK(prompt_growth_exclusion(means, capture, prompts, 1).count(1) == 0);
  CHECK(prompt_growth_exclusion(means, capture, prompts, 0).at(1) == std::vector<char>{1, 1, 0});
  prompts.vote_balance[1].pop_back();
  CHECK_THROWS_WITH(prompt_growth_exclusion(means, capture, prompts, 0.9),
                    Catch::Matchers::Contains("'clicked' was voted on a model of 2 Gaussians, "
                                              "this one has 3"));
  prompts.prompts[0].view = "v9";
  CHECK_THROWS_WITH(prompt_growth_exclusion(means, capture, prompts, 0.9),
                    Catch::Matchers::Contains("the capture has no view 'v9'"));
}
