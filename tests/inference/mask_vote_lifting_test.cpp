// FlashSplat's closed-form vote on hand-built blend weights, and on a rendered two-blob scene.
#include "nodes/inference/mask_vote_lifting.hpp"

#include <cmath>

#include "nodes/inference/prompt_segmentation.hpp"
#include "nodes/inference/selection_mask.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// One 2 x 1 view's blend weights, front to back per pixel.
struct Rows {
  std::vector<uint32_t> offsets, ids;
  std::vector<float> weights;
  PixelRowsView view() const { return {offsets.data(), ids.data(), weights.data()}; }
};

cv::Mat1b row_mask(bool left, bool right) {
  cv::Mat1b m(1, 2);
  m(0, 0) = left ? 255 : 0;
  m(0, 1) = right ? 255 : 0;
  return m;
}

}  // namespace

TEST_CASE("mask votes: weighted majority with FlashSplat's background bias",
          "[inference][mask_votes]") {
  // View a: pixel 0 = (g0 0.6, g1 0.3), pixel 1 = (g1 0.5, g2 0.2); view b: pixel 0 = (g1 0.4),
  // pixel 1 = (g0 0.1). Gaussian 3 is in no view.
  const Rows a{{0, 2, 4}, {0, 1, 1, 2}, {0.6f, 0.3f, 0.5f, 0.2f}};
  const Rows b{{0, 1, 2}, {1, 0}, {0.4f, 0.1f}};
  // Prompt 0: object = pixel 0 in both views. Prompt 1: no mask in view a, pixel 1 in view b.
  MaskVotes votes(4, 2);
  votes.add_view(a.view(), 2, 1, {row_mask(true, false), cv::Mat1b()});
  votes.add_view(b.view(), 2, 1, {row_mask(true, false), row_mask(false, true)});
  // Prompt 0: (background, object) = g0 (0.1, 0.6), g1 (0.5, 0.7), g2 (0.2, 0), g3 (0, 0).
  CHECK(votes.background(0, 0) == Approx(0.1));
  CHECK(votes.foreground(0, 0) == Approx(0.6));
  CHECK(votes.background(1, 0) == Approx(0.5));
  CHECK(votes.foreground(1, 0) == Approx(0.7));
  CHECK(votes.background(2, 0) == Approx(0.2));
  std::vector<float> score;
  CHECK(votes.object(0, 0, &score) == std::vector<uint8_t>{1, 1, 0, 0});
  CHECK(score[1] == Approx(0.7 / std::hypot(0.5, 0.7)));
  CHECK(score[3] == 0);
  // g1's normalised margin is (0.7 - 0.5) / 0.860 = 0.233: a bias of 0.3 turns it, not g0
  // (margin 0.822).
  CHECK(votes.object(0, 0.3) == std::vector<uint8_t>{1, 0, 0, 0});
  CHECK(votes.object(0, 0.2) == std::vector<uint8_t>{1, 1, 0, 0});
  // A Gaussian with only background votes, or none, stays background at any bias (FlashSplat's
  // code would put the unseen g3 in the object at a negative bias).
  CHECK(votes.object(0, -0.99) == std::vector<uint8_t>{1, 1, 0, 0});
  // Prompt 1 voted in view b alone: g0 (0, 0.1) object, g1 (0.4, 0) background.
  CHECK(votes.object(1, 0) == std::vector<uint8_t>{1, 0, 0, 0});
  // The balance (A_1 - A_0) / |A|: g0 (0.6 - 0.1) / 0.608, g1 0.2 / 0.860, g2 seen only outside
  // -1, g3 unseen 0; prompt 1: g0 1, g1 -1.
  const std::vector<float> balance = votes.balance(0);
  REQUIRE(balance.size() == 4);
  CHECK(balance[0] == Approx(0.5 / std::hypot(0.1, 0.6)));
  CHECK(balance[1] == Approx(0.2 / std::hypot(0.5, 0.7)));
  CHECK(balance[2] == Approx(-1.0));
  CHECK(balance[3] == 0);
  CHECK(votes.balance(1) == std::vector<float>{1.f, -1.f, 0.f, 0.f});
  CHECK_THROWS_AS(votes.add_view(a.view(), 2, 1, {row_mask(true, false)}), std::invalid_argument);
  CHECK_THROWS_AS(votes.add_view(a.view(), 2, 1, {cv::Mat1b(2, 2), cv::Mat1b()}),
                  std::invalid_argument);
}

TEST_CASE("mask votes: a rendered blob is lifted, what the view does not show is not",
          "[inference][mask_votes]") {
  // The two blobs of query_scene.hpp: a mask of the left half of the view lifts Gaussian 0 (the
  // left blob) and not Gaussian 1.
  const GaussianModel model = test::two_blobs();
  const Camera cam = test::query_camera();
  const RenderCache w = render_weights(model, cam, Pose{});
  cv::Mat1b left(cam.height, cam.width, uint8_t(0));
  left(cv::Rect(0, 0, cam.width / 2, cam.height)) = 255;
  MaskVotes votes(model.size(), 1);
  votes.add_view(w.pixel_rows(), cam.width, cam.height, {left});
  CHECK(votes.foreground(0, 0) > 1);  // it covers pixels: weights summed over them
  CHECK(votes.background(1, 0) > 1);
  CHECK(votes.object(0, 0) == std::vector<uint8_t>{1, 0});
}
