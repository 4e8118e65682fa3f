#include "nodes/association/memory_bank.hpp"

#include <cmath>
#include <numeric>
#include <vector>

#include <catch2/catch.hpp>

using namespace gslift;

namespace {

std::vector<uint32_t> ids(std::initializer_list<uint32_t> list) {
  return list;
}
std::vector<uint32_t> range(uint32_t begin, uint32_t end) {
  std::vector<uint32_t> r(end - begin);
  std::iota(r.begin(), r.end(), begin);
  return r;
}
std::vector<uint32_t> sorted(std::vector<uint32_t> v) {
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

// Three views of hand-picked Gaussian sets; every overlap below is worked out by hand.
//   view 1: A = {0..9}, B = {10..19}                    -> entries e0 = A, e1 = B
//   view 2: G1 = {0,1,2,20}: |G n e0| = 3, |G| = 4
//             paper gamma 3/4 = 0.75, Gaga 3/(4+3) = 0.43 -> e0 in both
//           G2 = {10, 21..29}: |G n e1| = 1, |G| = 10
//             paper 1/10 = 0.1 >= 0.1 -> e1; Gaga 1/11 = 0.09 < 0.1 -> new e2 = G2 (with 10)
//   view 3: H = {1, 2, 19, 40}
//             paper: e0 = {0..9, 20} 2/4 = 0.5, e1 = {10..29} \ {20} 1/4 -> e0, which gains 19, 40
//             Gaga: e0 2/6 = 0.33, e1 = {10..19} 1/5 = 0.2, e2 0 -> e0, which gains only the
//             unassigned 40 (19 already belongs to e1)
TEST_CASE("memory bank: paper and Gaga overlap formulas on a hand-built scene") {
  const std::vector<std::vector<uint32_t>> view1{range(0, 10), range(10, 20)};
  std::vector<uint32_t> g2 = range(21, 30);
  g2.insert(g2.begin(), 10);
  const std::vector<std::vector<uint32_t>> view2{ids({0, 1, 2, 20}), g2};
  const std::vector<std::vector<uint32_t>> view3{ids({1, 2, 19, 40})};

  SECTION("paper: gamma = |G n M| / |G|, M <- M u G") {
    MemoryBank bank(50, 0.1, false);
    CHECK(bank.add_view(view1) == std::vector<int>{1, 2});
    const std::vector<double> gamma = bank.overlaps(view2[1]);
    CHECK(gamma[0] == Approx(0.0));
    CHECK(gamma[1] == Approx(0.1));
    CHECK(bank.overlaps(view2[0])[0] == Approx(0.75));
    CHECK(bank.add_view(view2) == std::vector<int>{1, 2});
    CHECK(bank.overlaps(view3[0])[0] == Approx(0.5));
    CHECK(bank.overlaps(view3[0])[1] == Approx(0.25));
    CHECK(bank.add_view(view3) == std::vector<int>{1});
    REQUIRE(bank.entries() == 2);
    std::vector<uint32_t> e0 = range(0, 10);
    e0.insert(e0.end(), {19, 20, 40});
    CHECK(sorted(bank.entry(0)) == e0);
    std::vector<uint32_t> e1 = range(10, 20);
    const std::vector<uint32_t> rest = range(21, 30);
    e1.insert(e1.end(), rest.begin(), rest.end());
    CHECK(sorted(bank.entry(1)) == e1);
  }
  SECTION("gaga_compat: gamma = |G n M| / (|G| + |G n M|), joins gain only unassigned") {
    MemoryBank bank(50, 0.1, true);
    CHECK(bank.add_view(view1) == std::vector<int>{1, 2});
    CHECK(bank.overlaps(view2[0])[0] == Approx(3.0 / 7.0));
    CHECK(bank.overlaps(view2[1])[1] == Approx(1.0 / 11.0));
    CHECK(bank.add_view(view2) == std::vector<int>{1, 3});
    const std::vector<double> gamma = bank.overlaps(view3[0]);
    CHECK(gamma[0] == Approx(2.0 / 6.0));
    CHECK(gamma[1] == Approx(1.0 / 5.0));
    CHECK(gamma[2] == Approx(0.0));
    CHECK(bank.add_view(view3) == std::vector<int>{1});
    REQUIRE(bank.entries() == 3);
    std::vector<uint32_t> e0 = range(0, 10);
    e0.insert(e0.end(), {20, 40});
    CHECK(sorted(bank.entry(0)) == e0);
    CHECK(sorted(bank.entry(1)) == range(10, 20));
    CHECK(sorted(bank.entry(2)) == g2);  // the new entry took 10 although e1 holds it
  }
}

TEST_CASE("memory bank: an empty mask makes a new, empty entry") {
  MemoryBank bank(10, 0.1, false);
  CHECK(bank.add_view({ids({0, 1})}) == std::vector<int>{1});
  CHECK(bank.add_view({{}, ids({0})}) == std::vector<int>{2, 1});
  CHECK(bank.entry(1).empty());
}

// A 64x64 view cut into 2x2 patches of 32x32 pixels; mask 1 = the left half, mask 2 = the right
// half above row 32, the rest unlabelled.
//   mask 1, patch (0,0): Gaussians 0..9 at pixel (5,5), depths 1..10 -> front floor(0.2*10) = 2:
//           ids 0, 1
//   mask 1, patch (0,1) (rows >= 32): 10..12 at (5,40), depths 3,1,2 -> front max(0, 1) = 1: 11
//   mask 2, patch (1,0): 13..16 at (40,5), depths 4,3,2,1 -> 16
//   17 at (40,40) (unlabelled), 18 behind the camera (pixel -1): never candidates.
// Probability criterion: mask 1 has E = 13 candidates -> floor(2.6) = 2 most probable; Gaussians
// 9 and 12 get the highest probabilities. Mask 2: E = 4 -> max(floor(0.8), 1) = 1: Gaussian 13.
TEST_CASE("select_mask_gaussians: depth per patch, probability per mask, and their union") {
  cv::Mat1i partition = cv::Mat1i::zeros(64, 64);
  partition(cv::Rect(0, 0, 32, 64)).setTo(1);
  partition(cv::Rect(32, 0, 32, 32)).setTo(2);
  ProjectedCentres c;
  auto add = [&](int x, int y, float depth) {
    c.pixel.push_back(x < 0 ? -1 : y * 64 + x);
    c.depth.push_back(depth);
  };
  for (int k = 0; k < 10; ++k) add(5, 5, 1.f + k);
  add(5, 40, 3.f), add(5, 40, 1.f), add(5, 40, 2.f);
  for (int k = 0; k < 4; ++k) add(40, 5, 4.f - k);
  add(40, 40, 1.f);
  add(-1, 0, -1.f);
  std::vector<float> prob(c.pixel.size(), 0.1f);
  prob[9] = 0.9f, prob[12] = 0.8f, prob[13] = 0.7f;

  MemoryBankOptions o;
  o.patches = 2;
  o.criteria = AssociationCriteria::Depth;
  auto sets = select_mask_gaussians(partition, c, {}, o);
  REQUIRE(sets.size() == 2);
  CHECK(sets[0] == ids({0, 1, 11}));
  CHECK(sets[1] == ids({16}));
  o.criteria = AssociationCriteria::Probability;
  sets = select_mask_gaussians(partition, c, prob, o);
  CHECK(sets[0] == ids({9, 12}));
  CHECK(sets[1] == ids({13}));
  o.criteria = AssociationCriteria::Both;
  sets = select_mask_gaussians(partition, c, prob, o);
  CHECK(sets[0] == ids({0, 1, 9, 11, 12}));
  CHECK(sets[1] == ids({13, 16}));
  // The probability criterion without probabilities is an input error, not a crash.
  CHECK_THROWS(select_mask_gaussians(partition, c, {}, o));
}

// sigma = softmax(tau cos(w_c, f)) for f = (0, 2) against w = (1,0), (0,3), (-1,0): the cosines
// are 0, 1, 0, so sigma_1 = e^10 / (2 + e^10).
TEST_CASE(
    "gaussian_mask_probabilities: the view classifier's softmax of the mask under the centre") {
  cv::Mat1i partition = cv::Mat1i::zeros(4, 4);
  partition(0, 0) = 1;
  partition(0, 1) = 2;
  ProjectedCentres c;
  c.pixel = {0, 1, 5, -1};
  c.depth = {1, 1, 1, 1};
  const std::vector<float> features{0, 2, 0, 2, 0, 2, 0, 2};
  const std::vector<float> weights{1, 0, 0, 3, -1, 0};
  const auto p = gaussian_mask_probabilities(partition, c, features, 2, weights, 3, 10.0);
  const double e = std::exp(10.0);
  CHECK(p[0] == Approx(e / (2 + e)));
  CHECK(p[1] == Approx(1 / (2 + e)));
  CHECK(p[2] == 0.f);  // unlabelled pixel
  CHECK(p[3] == 0.f);  // not in the view
}

// A centre rounds to the pixel whose centre is nearest: x = 0.2 at z = 1 with fx = 10, cx = 2
// lands at u = 4.0 -> pixel 4 (covering [4, 5)); behind the camera -> -1.
TEST_CASE("project_centres: pixel of the rounded centre, -1 behind or outside") {
  Camera cam;
  cam.width = 8, cam.height = 6, cam.fx = cam.fy = 10, cam.cx = 2, cam.cy = 3;
  const std::vector<float> means{0.2f, 0.05f, 1.f, 0.f, 0.f, -1.f, 1.f, 0.f, 1.f};
  const ProjectedCentres c = project_centres(means, cam, Pose{});
  CHECK(c.pixel[0] == 3 * 8 + 4);
  CHECK(c.depth[0] == Approx(1.f));
  CHECK(c.pixel[1] == -1);
  CHECK(c.pixel[2] == -1);  // u = 12 >= width
}

// More than 300 masks (Gaga's uint8 maps wrap past 255): a 20x16 view with one mask per pixel and
// one Gaussian per mask makes 320 entries, and the consistent map keeps ids 256..320 apart.
TEST_CASE("memory bank: a view with 320 masks keeps 320 distinct labels") {
  cv::Mat1i partition(16, 20);
  std::vector<std::vector<uint32_t>> sets;
  for (int k = 0; k < 320; ++k) {
    partition(k / 20, k % 20) = k + 1;
    sets.push_back({static_cast<uint32_t>(k)});
  }
  MemoryBank bank(320, 0.1, false);
  const std::vector<int> labels = bank.add_view(sets);
  CHECK(bank.entries() == 320);
  const cv::Mat1i consistent = relabel_partition(partition, labels);
  CHECK(consistent(15, 19) == 320);
  CHECK(consistent(12, 15) == 256);
  CHECK(consistent(12, 16) == 257);
}
