// Adam against hand-computed updates, moment re-indexing, and the 3DGS learning-rate decay.
#include <cmath>

#include "nodes/splat/adam.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("adam's first two steps match a hand computation") {
  AdamGroup adam(2, AdamSettings{0.9, 0.999, 1e-8});
  std::vector<float> p = {1.0f, -2.0f};
  const std::vector<float> lr = {0.1f, 0.01f};
  // Step 1: m = 0.1 g, v = 0.001 g^2; bias-corrected m/v^.5 = sign(g) -> p -= lr sign(g).
  std::vector<float> g = {0.5f, -4.0f};
  adam.step(p.data(), g.data(), 1, lr.data());
  CHECK(p[0] == Approx(1.0 - 0.1).epsilon(1e-6));
  CHECK(p[1] == Approx(-2.0 + 0.01).epsilon(1e-6));
  // Step 2 with g0 = 0.25: m = 0.9*0.05 + 0.1*0.25 = 0.07, v = 0.999*0.00025 + 0.001*0.0625
  // = 0.00031225; m_hat = 0.07 / 0.19, v_hat = 0.00031225 / 0.001999.
  g = {0.25f, 0.0f};
  adam.step(p.data(), g.data(), 1, lr.data());
  const double m_hat = 0.07 / 0.19, v_hat = 0.00031225 / (1 - 0.999 * 0.999);
  CHECK(p[0] == Approx(0.9 - 0.1 * m_hat / (std::sqrt(v_hat) + 1e-8)).epsilon(1e-5));
  // Second entry: m = 0.9 * -0.4 = -0.36, v = 0.999 * 0.016; m_hat = -0.36/0.19.
  const double m1 = -0.36 / 0.19, v1 = 0.999 * 0.016 / (1 - 0.999 * 0.999);
  CHECK(p[1] == Approx(-1.99 - 0.01 * m1 / (std::sqrt(v1) + 1e-8)).epsilon(1e-5));
  CHECK(adam.steps_taken() == 2);
}

TEST_CASE("adam moments follow their rows through remap") {
  AdamGroup adam(1);
  std::vector<float> p = {0, 0, 0};
  const std::vector<float> g = {1, 2, 3};
  adam.step(p.data(), g.data(), 3, 0.1f);
  adam.remap({2, -1, 0, 0});  // keep row 2 first, a new row, row 0 twice (a clone)
  REQUIRE(adam.first_moment().size() == 4);
  CHECK(adam.first_moment()[0] == Approx(0.3f));
  CHECK(adam.first_moment()[1] == 0.f);
  CHECK(adam.first_moment()[2] == Approx(0.1f));
  CHECK(adam.first_moment()[3] == Approx(0.1f));
  CHECK(adam.second_moment()[0] == Approx(0.001f * 9));
}

TEST_CASE("exponential learning rate decays log-linearly") {
  CHECK(exponential_lr(1.6e-4, 1.6e-6, 0, 500) == Approx(1.6e-4));
  CHECK(exponential_lr(1.6e-4, 1.6e-6, 250, 500) == Approx(1.6e-5));  // geometric mean
  CHECK(exponential_lr(1.6e-4, 1.6e-6, 500, 500) == Approx(1.6e-6));
  CHECK(exponential_lr(1.6e-4, 1.6e-6, 900, 500) == Approx(1.6e-6));
}
