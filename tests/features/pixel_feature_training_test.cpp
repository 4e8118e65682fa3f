#include "nodes/features/pixel_feature_training.hpp"

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/pinhole.hpp"

using namespace gslift;

// One Gaussian in front of a 16x16 camera; every batch samples the centre pixel with the loss
// L = sum_c F_c(p) and the extra parameter e with L_e = -2 e: with constant gradients every Adam
// step moves each parameter by exactly its learning rate against the gradient's sign
// (m / (1 - b1^t) = g, v / (1 - b2^t) = g^2).
TEST_CASE("train_pixel_features: constant gradients move features and extras by lr per step") {
  GaussianModel model;
  model.resize(1);
  model.means[2] = 3.f;
  for (int c = 0; c < 3; ++c) model.log_scales[c] = std::log(0.5f);
  model.opacity_logits[0] = 2.f;
  std::vector<PixelRows> rows;
  rows.push_back(render_pixel_rows(model, test::centred_pinhole(16, 16, 20), Pose{}, 0.f));
  const std::vector<uint32_t> centre{8 * 16 + 8};
  float w = 0;
  rows[0].render(std::vector<float>{1.f}.data(), 1, centre, &w);
  REQUIRE(w > 0.5f);

  const int dim = 3;
  std::vector<float> features{0.1f, -0.2f, 0.3f};
  std::vector<float> extras{1.f, 2.f};
  int calls = 0;
  const PixelBatchStep step = [&](int, size_t b, const float* f, const float* e, PixelBatch& s) {
    s.view = 0;
    s.pixels = centre;
    std::vector<float> rendered(dim);
    rows[0].render(f, dim, s.pixels, rendered.data());
    s.loss = rendered[0] + rendered[1] + rendered[2];
    s.grad.assign(dim, 1.f);
    s.extra_offset = b;  // batch b owns extra b
    s.extra_grad = {-2.f};
    s.loss += -2.0 * e[b];
  };
  PixelTrainingSettings settings;
  settings.iterations = 3;
  settings.dim = dim;
  settings.lr = 0.01;
  settings.extra_lr = 0.5;
  double extra_term_loss = 0.25;
  std::vector<TrainingStep> steps;  // what the progress line is told
  const PixelTrainingLoss loss = train_pixel_features(
      rows, 2, settings, step, features, extras,
      [&](int, const float*, const float*, float*, float*) {
        ++calls;
        return extra_term_loss;
      },
      [&](const TrainingStep& s) { steps.push_back(s); });
  CHECK(calls == 3);
  // Steps done 1..3 of 3, each with the iteration's loss; no render, so no PSNR.
  REQUIRE(steps.size() == 3);
  for (int k = 0; k < 3; ++k) {
    CHECK(steps[k].step == k + 1);
    CHECK(steps[k].total == 3);
    CHECK(std::isnan(steps[k].train_psnr));
  }
  CHECK(steps[0].loss == loss.start);
  CHECK(steps[2].loss == loss.end);
  // Mean of the two batches' losses before any update, plus the extra term.
  const double start = w * (0.1 - 0.2 + 0.3) - 2.0 * (1 + 2) / 2.0 + 0.25;
  CHECK(loss.start == Approx(start).epsilon(1e-5));
  CHECK(features[0] == Approx(0.1 - 3 * 0.01).epsilon(1e-4));
  CHECK(features[1] == Approx(-0.2 - 3 * 0.01).epsilon(1e-4));
  CHECK(features[2] == Approx(0.3 - 3 * 0.01).epsilon(1e-4));
  CHECK(extras[0] == Approx(1 + 3 * 0.5).epsilon(1e-5));
  CHECK(extras[1] == Approx(2 + 3 * 0.5).epsilon(1e-5));
}
