// The tile-grouped selection mask against the full sparse product of the render cache.
#include "nodes/inference/selection_mask.hpp"

#include <cmath>

#include <tbb/global_control.h>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/inference/text_query.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// 400 random semi-transparent Gaussians in front of a 100 x 70 camera (partial tiles at the right
// and bottom edges), so pixels blend many of them in depth.
GaussianModel random_scene() {
  GaussianModel m;
  m.resize(400);
  RandomStream rng(stream_seed(0, "test.selection_mask"));
  for (size_t g = 0; g < m.size(); ++g) {
    const double z = rng.uniform(2.0, 4.0);
    m.means[3 * g + 0] = static_cast<float>(rng.uniform(-0.9, 0.9) * z / 2);
    m.means[3 * g + 1] = static_cast<float>(rng.uniform(-0.6, 0.6) * z / 2);
    m.means[3 * g + 2] = static_cast<float>(z);
    for (int a = 0; a < 3; ++a)
      m.log_scales[3 * g + a] = static_cast<float>(std::log(rng.uniform(0.03, 0.2)));
    m.opacity_logits[g] = static_cast<float>(rng.uniform(-2.0, 3.0));
  }
  return m;
}

}  // namespace

TEST_CASE("selection masks from tile-grouped pairs match the full render") {
  const GaussianModel model = random_scene();
  const Camera cam = test::centred_pinhole(100, 70, 60);
  const Pose pose;
  const QueryView full(model, cam, pose);
  const SelectionMasker fast(model, cam, pose);
  REQUIRE(fast.gaussian_count() == model.size());
  RandomStream rng(stream_seed(0, "test.selection_mask.flags"));
  for (double share : {0.0, 0.05, 0.3, 0.7, 1.0}) {
    std::vector<uint8_t> sel(model.size());
    for (uint8_t& s : sel) s = rng.chance(share);
    const cv::Mat1f reference = full.render(std::vector<float>(sel.begin(), sel.end()));
    const cv::Mat1f coverage = fast.coverage(sel);
    // The same weights summed in another order: equal to float rounding.
    CHECK(cv::norm(coverage, reference, cv::NORM_INF) < 1e-5);
    if (share == 1.0) CHECK(cv::norm(reference, cv::NORM_INF) > 0.9);  // opaque somewhere
    for (float t : {0.1f, 0.5f, 0.9f}) {
      const cv::Mat1b mask = fast.mask(sel, t);
      const cv::Mat1b ref = full.mask(std::vector<float>(sel.begin(), sel.end()), t);
      // An answer may differ only where the full render's alpha is within rounding of t.
      for (int y = 0; y < mask.rows; ++y)
        for (int x = 0; x < mask.cols; ++x)
          if (mask(y, x) != ref(y, x)) CHECK(std::abs(reference(y, x) - t) < 1e-5f);
      CHECK(cv::countNonZero(mask != ref) <= 2);
    }
  }
  // Deterministic at any thread count.
  std::vector<uint8_t> half(model.size());
  for (size_t g = 0; g < half.size(); g += 2) half[g] = 1;
  const cv::Mat1f two = fast.coverage(half);
  cv::Mat1f one;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = fast.coverage(half);
  }
  CHECK(cv::norm(one, two, cv::NORM_INF) == 0);
  CHECK_THROWS_AS(fast.mask(std::vector<uint8_t>(3), 0.5f), InputError);
}

TEST_CASE("selection mask of one of two blobs") {
  const GaussianModel model = test::two_blobs();
  const SelectionMasker fast(model, test::query_camera(), Pose{});
  const cv::Mat1b right = fast.mask({0, 1}, 0.5f);
  CHECK(right(24, 47) == 255);
  CHECK(right(24, 17) == 0);
  const cv::Mat1b none = fast.mask({0, 0}, 0.5f);
  CHECK(cv::countNonZero(none) == 0);
}
