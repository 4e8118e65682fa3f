#include "nodes/features/contrastive_features.hpp"

#include <cmath>
#include <vector>

#include <tbb/global_control.h>
#include <Eigen/Core>

#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"
#include "runtime/node.hpp"
#include "tests/features/two_groups.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

double cosine(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.dot(b) / (a.norm() * b.norm());
}

}  // namespace

TEST_CASE("contrastive features separate two groups seen through their masks", "[features]") {
  test::TwoGroups s = test::two_groups();
  ContrastiveOptions o;
  o.iterations = 300;
  o.dim = 8;
  o.pixels_per_iteration = 64;
  o.seed = 3;
  const ContrastiveResult r = train_contrastive_features(s.model, s.capture, s.masks, o);
  REQUIRE(r.model.feature_dim == 8);
  REQUIRE(r.model.features.size() == s.model.size() * 8);
  CHECK(r.masks == 4);  // the held-out view's mask is not trained on
  CHECK(r.loss_end < 0.5 * r.loss_start);
  CHECK(r.model.means == s.model.means);  // geometry frozen

  auto feature = [&](int i) {
    return Eigen::Map<const Eigen::VectorXf>(r.model.features.data() + 8 * i, 8)
        .cast<double>()
        .eval();
  };
  Eigen::VectorXd mean[2] = {Eigen::VectorXd::Zero(8), Eigen::VectorXd::Zero(8)};
  for (size_t i = 0; i < s.model.size(); ++i) mean[s.group[i]] += feature(int(i));
  CHECK(cosine(mean[0], mean[1]) < 0.2);
  for (int g = 0; g < 2; ++g) {
    double within = 0;
    int count = 0;
    for (size_t i = 0; i < s.model.size(); ++i)
      if (s.group[i] == g) {
        within += cosine(feature(int(i)), mean[g]);
        ++count;
      }
    CHECK(within / count > 0.8);
  }
}

TEST_CASE("contrastive features do not depend on the thread count", "[features]") {
  test::TwoGroups s = test::two_groups();
  ContrastiveOptions o;
  o.iterations = 10;
  o.dim = 4;
  o.pixels_per_iteration = 32;
  std::vector<float> single;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    single = train_contrastive_features(s.model, s.capture, s.masks, o).model.features;
  }
  CHECK(train_contrastive_features(s.model, s.capture, s.masks, o).model.features == single);
  o.seed = 1;
  CHECK(train_contrastive_features(s.model, s.capture, s.masks, o).model.features != single);
}

TEST_CASE("contrastive features reject bad masks", "[features]") {
  test::TwoGroups s = test::two_groups();
  ContrastiveOptions o;
  o.iterations = 1;
  MaskSet unknown = s.masks;
  unknown.views[0].view = "nowhere";
  CHECK_THROWS_WITH(train_contrastive_features(s.model, s.capture, unknown, o),
                    Catch::Contains("nowhere"));
  MaskSet wrong = s.masks;
  wrong.views[1].masks[0].pixels = cv::Mat1b::zeros(10, 10);
  CHECK_THROWS_AS(train_contrastive_features(s.model, s.capture, wrong, o), InputError);
  MaskSet empty;
  CHECK_THROWS_AS(train_contrastive_features(s.model, s.capture, empty, o), InputError);
}

TEST_CASE("contrastive features keep the cached rows above min_weight", "[features]") {
  test::TwoGroups s = test::two_groups();
  ContrastiveOptions o;
  o.iterations = 1;
  // Expected with min_weight 0: every (pixel, Gaussian) pair of the two training views, as
  // offsets (one per pixel + 1), ids and weights.
  RenderSettings weights_only;
  weights_only.rgb = false;
  weights_only.alpha = true;
  size_t all = 0, above = 0;
  for (int v = 0; v < 2; ++v) {
    const View& view = s.capture.views[v];
    const RenderCache cache(render(s.model, view.camera, view.pose, weights_only));
    all += 4 * (cache.pixel_offsets().size() + 2 * cache.entries());
    above += 4 * cache.pixel_offsets().size();
    for (float w : cache.weights()) above += w >= 0.2f ? 8 : 0;
  }
  o.min_weight = 0;
  CHECK(train_contrastive_features(s.model, s.capture, s.masks, o).cache_bytes == all);
  o.min_weight = 0.2;
  CHECK(train_contrastive_features(s.model, s.capture, s.masks, o).cache_bytes == above);
  CHECK(above < all);
}
