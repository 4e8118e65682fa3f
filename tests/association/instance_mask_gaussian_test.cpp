// Association (LangOR §1.3 "Matching") on hand-made feature maps, masks and prototypes, where the
// instance of every pixel, mask and Gaussian can be read off the numbers.
#include "nodes/association/instance_mask_gaussian.hpp"

#include <tbb/global_control.h>

#include "base/random.hpp"
#include "runtime/node.hpp"
#include "tests/association/fixed_text_encoder.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using test::vec3;

namespace {

constexpr int kW = 12, kH = 8;

// Three prototypes: e0, e1, e2.
LiftedInstances three_prototypes() {
  LiftedInstances l;
  l.prototypes = Eigen::Matrix3f::Identity();
  return l;
}

// Columns 0..3 look like instance 0, 4..7 like instance 1, 8..11 like instance 2.
FeatureMap striped_view() {
  FeatureMap f{kW, kH, 3, UninitVector<float>(kW * kH * 3, 0.f)};
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      float* p = f.values.data() + (y * kW + x) * 3;
      if (x < 4) {
        p[0] = 1, p[1] = 0.1f;
      } else if (x < 8) {
        p[0] = 0.1f, p[1] = 1;
      } else {
        p[1] = 0.2f, p[2] = 1;
      }
    }
  return f;
}

Mask box(int x0, int x1, int y0, int y1, const std::string& label) {
  Mask m;
  m.pixels = cv::Mat1b::zeros(kH, kW);
  m.pixels(cv::Range(y0, y1), cv::Range(x0, x1)).setTo(255);
  m.label = label;
  return m;
}

struct Scene {
  std::vector<FeatureMap> maps;
  MaskSet masks;
  LiftedInstances lifted = three_prototypes();
};

// View 0: "table" over instance 0, "chair" over instance 1, and a "box" over 8 pixels of
// instance 2's stripe whose CVP samples say otherwise: 3 sampled pixels labelled 0, 3 sampled
// noise pixels, 2 unsampled pixels (nearest: instance 2). Noise does not vote, so 0 wins 3 : 2
// (were noise pixels matched by their nearest prototype, 2 would win 5 : 3).
// View 1: "table" and "seat" over instances 0 and 1, and a mislabelled "lamp" over columns 0..4
// (32 table pixels, 8 chair pixels -> instance 0). Nothing else covers instance 2.
Scene scene() {
  Scene s;
  s.maps = {striped_view(), striped_view()};
  ViewMasks v0{"v0",
               {box(0, 4, 0, kH, "table"), box(4, 8, 0, kH, "chair"), box(8, 12, 0, 2, "box")}};
  ViewMasks v1{"v1",
               {box(0, 4, 0, kH, "table"), box(4, 8, 0, kH, "seat"), box(0, 5, 0, kH, "lamp")}};
  s.masks.views = {v0, v1};
  const int labels[6] = {0, 0, 0, -1, -1, -1};
  for (int i = 0; i < 6; ++i) {
    s.lifted.samples.push_back({0, 2, 8 + i % 4, i / 4});
    s.lifted.labels.push_back(labels[i]);
  }
  return s;
}

// The scene's views as the training views mask_views of some MaskSet.
TrainingFeatureMaps training_views(const Scene& s, std::vector<int> mask_views) {
  TrainingFeatureMaps views;
  views.mask_views = std::move(mask_views);
  views.masks = s.masks;
  views.maps = s.maps;
  return views;
}

test::FixedTextEncoder furniture_encoder() {
  return test::FixedTextEncoder({{"table", vec3(1, 0, 0)},
                                 {"chair", vec3(0, 1, 0)},
                                 {"seat", vec3(0, 0.6f, 0.8f)},
                                 {"lamp", vec3(0, 0, 1)},
                                 {"box", vec3(0, 0.8f, 0.6f)}});
}

GaussianModel six_gaussians() {
  GaussianModel m;
  m.feature_dim = 3;
  m.resize(6);
  const float f[6][3] = {{2, 0.1f, 0}, {0.1f, 1, 0}, {0, 0, 0},
                         {1, 1, 0},    {-1, 0, 0},   {0, 0.1f, 1}};
  for (int g = 0; g < 6; ++g)
    for (int k = 0; k < 3; ++k) m.features[g * 3 + k] = f[g][k];
  return m;
}

}  // namespace

TEST_CASE("masks take the majority instance of their pixels, sampled pixels keep their cluster") {
  const Scene s = scene();
  const auto matched = match_masks(s.maps, s.masks, s.lifted);
  REQUIRE(matched.size() == 2);
  CHECK(matched[0] == std::vector<int>{0, 1, 0});
  CHECK(matched[1] == std::vector<int>{0, 1, 0});

  // Without the samples every "box" pixel is unsampled and nearest to instance 2.
  Scene unsampled = s;
  unsampled.lifted.samples.clear();
  unsampled.lifted.labels.clear();
  CHECK(match_masks(unsampled.maps, unsampled.masks, unsampled.lifted)[0][2] == 2);
}

TEST_CASE("the IoU vote picks the instance whose region fits the mask, not the most pixels") {
  // Columns 0..3 look like instance 0 (region 32 px), 4..11 like instance 1 (64 px). A "table"
  // mask over columns 0..8 (72 px) holds 32 pixels of instance 0 and 40 of instance 1: the count
  // takes 1; by IoU instance 0 fits better, 32 / (72 + 32 - 32) = 0.444 against
  // 40 / (72 + 64 - 40) = 0.417.
  FeatureMap f{kW, kH, 3, UninitVector<float>(kW * kH * 3, 0.f)};
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) f.values[(y * kW + x) * 3 + (x < 4 ? 0 : 1)] = 1;
  Scene s;
  s.maps = {f};
  s.masks.views = {ViewMasks{"v0", {box(0, 9, 0, kH, "table")}}};
  CHECK(match_masks(s.maps, s.masks, s.lifted)[0][0] == 1);
  CHECK(match_masks(s.maps, s.masks, s.lifted, MaskVote::Iou, 0.5f)[0][0] == 0);

  // Columns 10..11 with a feature of cos 0.28 to instance 1 (below min_similarity 0.5): out of
  // its region, which shrinks to 48 px, and its IoU rises to 40 / (72 + 48 - 40) = 0.5 > 0.444.
  // With min_similarity -1 they count again and instance 0 wins as before.
  for (int y = 0; y < kH; ++y)
    for (int x = 10; x < kW; ++x) f.values[(y * kW + x) * 3 + 2] = 3.4f;  // (0, 1, 3.4)
  s.maps = {f};
  s.lifted.prototypes = Eigen::Matrix3f::Identity().topRows(2);
  CHECK(match_masks(s.maps, s.masks, s.lifted, MaskVote::Iou, 0.5f)[0][0] == 1);
  CHECK(match_masks(s.maps, s.masks, s.lifted, MaskVote::Iou, -1.f)[0][0] == 0);
}

TEST_CASE("Gaussians take their most similar prototype unless unseen or dissimilar") {
  const GaussianModel model = six_gaussians();
  const std::vector<float> contribution = {5, 5, 5, 5, 5, 0.001f};
  AssociationParams p;  // min_similarity 0.5, min_contribution 0.01
  // g0 ~ e0; g1 ~ e1; g2 zero; g3 cos 0.707 with e0 and e1 (tie: lower id); g4 cos <= 0 with all;
  // g5 ~ e2 but never seen in training.
  CHECK(match_gaussians(model, contribution, Eigen::Matrix3f::Identity(), p) ==
        std::vector<int32_t>{0, 1, -1, 0, -1, -1});
  p.min_similarity = -1;  // g4: cos -1, 0, 0 -> instance 1 (tie between 1 and 2)
  CHECK(match_gaussians(model, {}, Eigen::Matrix3f::Identity(), p) ==
        std::vector<int32_t>{0, 1, -1, 0, 1, 2});
  p.min_similarity = 0.71f;  // g3's 0.7071 no longer qualifies
  CHECK(match_gaussians(model, {}, Eigen::Matrix3f::Identity(), p)[3] == -1);
}

TEST_CASE("association: instance labels from the masks, unmatched instance unlabelled") {
  const Scene s = scene();
  const auto enc = furniture_encoder();
  const GaussianModel model = six_gaussians();
  // The two views are training views 0 and 2 of a MaskSet whose view 1 is held out.
  const TrainingFeatureMaps views = training_views(s, {0, 2});
  MaskSet all = s.masks;
  all.views.insert(all.views.begin() + 1, ViewMasks{"held_out", {box(0, 4, 0, kH, "lamp")}});
  const InstanceAssociation a = associate_instances(views, all, s.lifted, model, enc, {});
  const InstanceSet& set = a.instances;
  REQUIRE(set.size() == 3);
  // Instance 0's masks: table, box, table, lamp. Summed cosines: table 0 + 1 + 0 = 1 (twice),
  // box 0 + 0 + 0.6 = 0.6, lamp 0 + 0.6 + 0 = 0.6: the mislabelled lamp and box lose.
  CHECK(set.labels[0] == "table");
  CHECK(Eigen::VectorXf(set.semantics.row(0)).isApprox(vec3(1, 0, 0)));
  // Instance 1: chair and seat, two masks: their normalised average (0, 1.6, 0.8) / |.|.
  CHECK(set.labels[1] == "chair");
  CHECK(Eigen::VectorXf(set.semantics.row(1)).isApprox(vec3(0, 0.894427f, 0.447214f), 1e-5f));
  // Instance 2: no mask chose it.
  CHECK(set.labels[2].empty());
  CHECK(set.semantics.row(2).norm() == 0.f);
  // Indexed like the MaskSet given: the held-out view's mask is not matched.
  CHECK(set.mask_instance == std::vector<std::vector<int>>{{0, 1, 0}, {-1}, {0, 1, 0}});
  CHECK(a.training_masks == 6);
  CHECK(a.matched_masks == 6);
  CHECK(set.prototypes.isApprox(s.lifted.prototypes));
  CHECK(a.gaussian_instance == std::vector<int32_t>{0, 1, -1, 0, -1, 2});
}

TEST_CASE("association rejects feature maps that do not come from the masks given") {
  const Scene s = scene();
  TrainingFeatureMaps views = training_views(s, {0, 1});
  MaskSet other = s.masks;
  other.views[1].masks.pop_back();
  CHECK_THROWS_AS(
      associate_instances(views, other, s.lifted, six_gaussians(), furniture_encoder(), {}),
      InputError);
  views.mask_views = {0, 2};
  CHECK_THROWS_AS(
      associate_instances(views, s.masks, s.lifted, six_gaussians(), furniture_encoder(), {}),
      InputError);
}

TEST_CASE("association rejects lifted instances that do not come from the masks") {
  Scene s = scene();
  const GaussianModel model = six_gaussians();
  SECTION("a sample outside its mask") {
    s.lifted.samples[0] = {0, 0, 9, 0};  // mask 0 covers columns 0..3
    CHECK_THROWS_AS(match_masks(s.maps, s.masks, s.lifted), InputError);
  }
  SECTION("a sample naming a mask the view does not have") {
    s.lifted.samples[0] = {1, 7, 0, 0};
    CHECK_THROWS_AS(match_masks(s.maps, s.masks, s.lifted), InputError);
  }
  SECTION("prototypes of another width") {
    s.lifted.prototypes = Eigen::MatrixXf::Identity(3, 4);
    CHECK_THROWS_AS(match_masks(s.maps, s.masks, s.lifted), InputError);
    CHECK_THROWS_AS(match_gaussians(model, {}, s.lifted.prototypes, {}), InputError);
  }
}

TEST_CASE("association does not depend on the thread count") {
  // Random features, 5 prototypes, 4 random masks per view, 2000 Gaussians.
  RandomStream rng(7);
  auto normal = [&] { return static_cast<float>(rng.normal()); };
  auto coord = [&] { return rng.below(41); };
  Scene s;
  s.lifted.prototypes = Eigen::MatrixXf::NullaryExpr(5, 3, normal);
  for (int v = 0; v < 3; ++v) {
    FeatureMap f{64, 48, 3, UninitVector<float>(64 * 48 * 3, 0.f)};
    for (float& x : f.values) x = normal();
    s.maps.push_back(std::move(f));
    ViewMasks vm{"v" + std::to_string(v), {}};
    for (int m = 0; m < 4; ++m) {
      Mask mask;
      mask.pixels = cv::Mat1b::zeros(48, 64);
      const int x = coord(), y = coord() / 2;
      mask.pixels(cv::Rect(x, y, 20, 20)).setTo(255);
      vm.masks.push_back(mask);
    }
    s.masks.views.push_back(vm);
  }
  GaussianModel model;
  model.feature_dim = 3;
  model.resize(2000);
  for (float& x : model.features) x = normal();
  std::vector<float> contribution(2000);
  for (float& c : contribution) c = std::abs(normal());

  const auto run = [&] {
    return std::make_pair(match_masks(s.maps, s.masks, s.lifted),
                          match_gaussians(model, contribution, s.lifted.prototypes, {}));
  };
  const auto many = run();
  decltype(run()) one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = run();
  }
  CHECK(one == many);
  int assigned = 0;
  for (const int32_t k : many.second) assigned += k >= 0;
  CHECK(assigned > 100);  // the comparison is not between two all -1 vectors
  CHECK(assigned < 2000);
}
