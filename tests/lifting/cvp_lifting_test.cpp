// CVP and mask-level lifting on synthetic feature maps: two objects, two views, known features.
#include "nodes/lifting/cvp_lifting.hpp"

#include "base/random.hpp"
#include "nodes/lifting/cluster_agreement.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

constexpr int kW = 24, kH = 16, kD = 4;

// Left half of each view shows object A (feature ~ e0), right half object B (~ e1), with small
// per-pixel noise; one mask per object per view.
struct Scene {
  std::vector<FeatureMap> views;
  MaskSet masks;
};

Scene two_objects(int views) {
  Scene s;
  RandomStream rng(3);
  for (int v = 0; v < views; ++v) {
    FeatureMap f{kW, kH, kD, UninitVector<float>(kW * kH * kD, 0.f)};
    cv::Mat1b left = cv::Mat1b::zeros(kH, kW), right = cv::Mat1b::zeros(kH, kW);
    left(cv::Rect(0, 0, kW / 2, kH)).setTo(255);
    right(cv::Rect(kW / 2, 0, kW / 2, kH)).setTo(255);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        float* p = f.values.data() + (y * kW + x) * kD;
        for (int k = 0; k < kD; ++k) p[k] = static_cast<float>(rng.normal(0.0, 0.02));
        p[x < kW / 2 ? 0 : 1] += 1.f;
      }
    s.views.push_back(std::move(f));
    ViewMasks vm;
    vm.view = "v" + std::to_string(v);
    vm.masks.push_back({left, "a"});
    vm.masks.push_back({right, "b"});
    s.masks.views.push_back(std::move(vm));
  }
  return s;
}

}  // namespace

TEST_CASE("CVP lifting finds the two objects across views and their prototypes (Eq. 5)") {
  const Scene s = two_objects(2);
  CvpLiftingParams p;
  p.samples_per_mask = 60;
  p.seed = 11;
  const LiftedInstances r = cvp_lifting(s.views, s.masks, p);
  REQUIRE(r.prototypes.rows() == 2);
  REQUIRE(r.samples.size() == r.labels.size());
  CHECK(r.samples.size() <= 4 * 60);
  CHECK(r.samples.size() > 100);  // duplicates removed, most draws distinct
  // Every non-noise sample's label agrees with the object it was drawn from, in both views.
  std::vector<int> truth;
  for (const auto& smp : r.samples) truth.push_back(smp.mask);
  std::vector<int> kept_labels, kept_truth;
  for (size_t i = 0; i < r.labels.size(); ++i)
    if (r.labels[i] >= 0) {
      kept_labels.push_back(r.labels[i]);
      kept_truth.push_back(truth[i]);
    }
  CHECK(kept_labels.size() > r.labels.size() * 9 / 10);
  CHECK(same_partition(kept_labels, kept_truth));
  // Prototypes are the mean features: ~e0 and ~e1.
  for (int c = 0; c < 2; ++c) {
    const Eigen::VectorXf proto = r.prototypes.row(c).transpose();
    const int axis = proto[0] > proto[1] ? 0 : 1;
    CHECK(proto[axis] == Approx(1.0).margin(0.02));
    CHECK(proto[1 - axis] == Approx(0.0).margin(0.02));
  }
  // Deterministic for a seed.
  CHECK(cvp_lifting(s.views, s.masks, p).labels == r.labels);
}

TEST_CASE("pixels no Gaussian covers (zero features) are noise, not a failed capture") {
  // The top rows of view 0 render nothing: their features are zero, which has no cosine
  // distance. HDBSCAN used to reject the whole capture (the stability matrix found it).
  Scene s = two_objects(2);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < kW; ++x) std::fill_n(s.views[0].values.data() + (y * kW + x) * kD, kD, 0.f);
  CvpLiftingParams p;
  p.samples_per_mask = 60;
  p.seed = 11;
  const LiftedInstances r = cvp_lifting(s.views, s.masks, p);
  REQUIRE(r.prototypes.rows() == 2);
  int zero = 0, zero_labelled = 0, kept = 0;
  std::vector<int> kept_labels, kept_truth;
  for (size_t i = 0; i < r.samples.size(); ++i) {
    const bool uncovered = r.samples[i].view == 0 && r.samples[i].y < 4;
    zero += uncovered;
    zero_labelled += uncovered && r.labels[i] >= 0;
    if (!uncovered && r.labels[i] >= 0) {
      ++kept;
      kept_labels.push_back(r.labels[i]);
      kept_truth.push_back(r.samples[i].mask);
    }
  }
  CHECK(zero > 0);
  CHECK(zero_labelled == 0);
  CHECK(kept > int(r.samples.size()) * 6 / 10);
  CHECK(same_partition(kept_labels, kept_truth));
}

TEST_CASE("CVP sampling concentrates on mask centres (Eq. 4)") {
  const Scene s = two_objects(1);
  CvpLiftingParams p;
  p.samples_per_mask = 400;
  p.hdbscan.min_cluster_size = 5;
  const LiftedInstances r = cvp_lifting(s.views, s.masks, p);
  // The left mask spans x in [0, 12), centre 5.5: its central third holds more distinct samples
  // than its outer third on the boundary side.
  int centre = 0, edge = 0;
  for (const auto& smp : r.samples)
    if (smp.mask == 0) {
      centre += smp.x >= 4 && smp.x < 8;
      edge += smp.x < 4;
    }
  CHECK(centre > edge);
}

TEST_CASE("mask-level lifting: one prototype per mask, clustered across views") {
  const Scene s = two_objects(3);
  const LiftedInstances r = mask_level_lifting(s.views, s.masks, MaskLevelLiftingParams{});
  REQUIRE(r.samples.size() == 6);
  CHECK(same_partition(r.labels, {0, 1, 0, 1, 0, 1}));
  CHECK(r.prototypes.rows() == 2);
}

TEST_CASE("lifting params: each node's defaults are its options' own, a wrong metric an error") {
  // Mask level: an instance is a few masks (2, nearest other mask); cosine as CVP.
  const MaskLevelLiftingParams m;
  CHECK(m.hdbscan.min_cluster_size == 2);
  CHECK(m.hdbscan.min_samples == 1);
  CHECK(m.hdbscan.metric == HdbscanMetric::Cosine);
  CHECK(m.cannot_link_iou == 0.5);
  const auto specs = mask_level_lifting_param_table().specs();
  REQUIRE(specs.size() == 5);
  CHECK(specs[0].name == "min_cluster_size");
  CHECK(std::get<int64_t>(*specs[0].default_value) == 2);
  CHECK(specs[3].name == "metric");
  CHECK(std::get<std::string>(*specs[3].default_value) == "cosine");
  // CVP: its three sampling params, then the same clustering params with CVP's defaults.
  const auto cvp = cvp_lifting_param_table().specs();
  REQUIRE(cvp.size() == 8);
  CHECK(cvp[3].name == "min_cluster_size");
  CHECK(std::get<int64_t>(*cvp[3].default_value) == 10);
  CHECK(cvp_lifting_param_table()
            .read({{"metric", std::string("euclidean")}, {"sigma", 0.7}})
            .hdbscan.metric == HdbscanMetric::Euclidean);
  CHECK_THROWS_AS(mask_level_lifting_param_table().read({{"metric", std::string("manhattan")}}),
                  std::invalid_argument);
  CvpLiftingParams bad;
  bad.sigma = 0;
  bad.hdbscan.min_cluster_size = 1;
  CHECK(cvp_lifting_param_table().check(bad).size() == 2);
}

TEST_CASE("lifting rejects mismatched inputs") {
  Scene s = two_objects(2);
  s.masks.views.pop_back();
  CHECK_THROWS_AS(cvp_lifting(s.views, s.masks, CvpLiftingParams{}), std::invalid_argument);
  Scene t = two_objects(1);
  t.masks.views[0].masks[0].pixels = cv::Mat1b::zeros(3, 3);
  CHECK_THROWS_AS(mask_level_lifting(t.views, t.masks, MaskLevelLiftingParams{}),
                  std::invalid_argument);
}

TEST_CASE("masks of one view that barely overlap are cannot-linked, duplicates are not") {
  auto rect = [](int x0, int x1) {
    cv::Mat1b m = cv::Mat1b::zeros(10, 20);
    m(cv::Rect(x0, 0, x1 - x0, 10)) = 255;
    return m;
  };
  MaskSet masks;
  masks.views.resize(2);
  // View 0: a = [0, 10), b = [10, 20), c = [1, 10) (IoU with a 0.9: the same object boxed
  // twice). View 1: d = [0, 8), e = [4, 12) (IoU 4 / 12 = 0.33).
  for (auto [x0, x1] : {std::pair{0, 10}, {10, 20}, {1, 10}})
    masks.views[0].masks.push_back({rect(x0, x1), "x"});
  for (auto [x0, x1] : {std::pair{0, 8}, {4, 12}})
    masks.views[1].masks.push_back({rect(x0, x1), "x"});
  CHECK(mask_group_ids(masks) == std::vector<std::vector<int>>{{0, 1, 2}, {3, 4}});
  using Pairs = std::vector<std::pair<int, int>>;
  CHECK(same_view_cannot_links(masks, 0.5) == Pairs{{0, 1}, {1, 2}, {3, 4}});
  CHECK(same_view_cannot_links(masks, 0.3) == Pairs{{0, 1}, {1, 2}});
  CHECK(same_view_cannot_links(masks, 0.0).empty());
}
