// SAGA's correspondence loss: K on hand-built mask sets, the loss on hand-computed features, and
// its gradient against central finite differences.
#include "nodes/features/correspondence_loss.hpp"

#include <cmath>

#include "base/random.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("K is the IoU of the pixels' mask sets, -1 when they share none") {
  // Pixel 0 in masks {0, 1}, pixel 1 in {1, 2}, pixel 2 in {3}, pixel 3 in {0, 1}; mask 70 is
  // in the second word.
  MaskMembership m;
  m.words = 2;
  m.bits = {0b011, 0, 0b110, 0, 0b1000, 0, 0b011, uint64_t(1) << 6};
  CHECK(mask_set_affinity(m.pixel(0), m.pixel(1), 2) == Approx(1.0 / 3.0));  // {1} / {0,1,2}
  CHECK(mask_set_affinity(m.pixel(0), m.pixel(2), 2) == -1.f);
  CHECK(mask_set_affinity(m.pixel(0), m.pixel(0), 2) == 1.f);
  CHECK(mask_set_affinity(m.pixel(0), m.pixel(3), 2) == Approx(2.0 / 3.0));  // {0,1} / {0,1,70}
  const Eigen::MatrixXf k = correspondence_kernel(m, {0, 1, 2});
  CHECK(k(0, 0) == 0.f);
  CHECK(k(0, 1) == Approx(1.0 / 3.0));
  CHECK(k(1, 0) == k(0, 1));
  CHECK(k(1, 2) == -1.f);
}

TEST_CASE("loss on hand-computed features") {
  // Three pixels: F0 = (1, 0), F1 = (2, 2) (cos 0.7071 with F0), F2 = (0, -3) (cos 0 with F0,
  // -0.7071 with F1). K01 = 1, K02 = -1, K12 = -1:
  // L = -(1 * 0.7071 + (-1) * 0 + (-1) * (-0.7071)) / 3 = -0.4714.
  Eigen::MatrixXf f(3, 2);
  f << 1, 0, 2, 2, 0, -3;
  Eigen::MatrixXf k(3, 3);
  k << 0, 1, -1, 1, 0, -1, -1, -1, 0;
  CHECK(correspondence_loss(f, k, nullptr) == Approx(-2 * std::sqrt(0.5) / 3));
  // Perfectly arranged features: same-mask pixels parallel, others opposite: L = -1.
  Eigen::MatrixXf ideal(3, 1);
  ideal << 1, 1, -1;
  Eigen::MatrixXf k2(3, 3);
  k2 << 0, 1, -1, 1, 0, -1, -1, -1, 0;
  CHECK(correspondence_loss(ideal, k2, nullptr) == Approx(-1.0));
}

TEST_CASE("gradient of the correspondence loss against finite differences") {
  RandomStream rng(stream_seed(1, "test.correspondence"));
  const int p = 7, d = 5;
  Eigen::MatrixXf f(p, d);
  for (int i = 0; i < p; ++i)
    for (int c = 0; c < d; ++c) f(i, c) = static_cast<float>(rng.normal());
  Eigen::MatrixXf k = Eigen::MatrixXf::Zero(p, p);
  for (int i = 0; i < p; ++i)
    for (int j = i + 1; j < p; ++j) {
      const double r = rng.uniform();
      k(i, j) = k(j, i) = r < 0.4 ? -1.f : static_cast<float>(r);
    }
  Eigen::MatrixXf grad;
  correspondence_loss(f, k, &grad);
  const float eps = 1e-2f;
  double max_err = 0, max_grad = 0;
  for (int i = 0; i < p; ++i)
    for (int c = 0; c < d; ++c) {
      Eigen::MatrixXf plus = f, minus = f;
      plus(i, c) += eps;
      minus(i, c) -= eps;
      const double fd =
          (correspondence_loss(plus, k, nullptr) - correspondence_loss(minus, k, nullptr)) /
          (2 * eps);
      max_err = std::max(max_err, std::abs(fd - grad(i, c)));
      max_grad = std::max(max_grad, double(std::abs(grad(i, c))));
    }
  CHECK(max_grad > 1e-3);
  CHECK(max_err < 2e-3 * max_grad);
  // A zero feature row counts as cos 0 and gets no gradient.
  f.row(2).setZero();
  correspondence_loss(f, k, &grad);
  CHECK(grad.row(2).norm() == 0.f);
}
