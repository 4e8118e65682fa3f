#include "nodes/features/classifier_loss.hpp"

#include <cmath>
#include <functional>
#include <vector>

#include <catch2/catch.hpp>

#include "base/random.hpp"

using namespace gslift;

namespace {

// Central difference of f at x[k].
double central(std::vector<float>& x, size_t k, const std::function<double()>& f, float h) {
  const float keep = x[k];
  x[k] = keep + h;
  const double up = f();
  x[k] = keep - h;
  const double down = f();
  x[k] = keep;
  return (up - down) / (double(x[k] + h) - double(x[k] - h));
}

std::vector<float> random_vector(size_t n, RandomStream& rng) {
  std::vector<float> v(n);
  for (float& x : v) x = static_cast<float>(rng.normal());
  return v;
}

}  // namespace

// Eq. 6-7 (cosine logits, tau = 10) on 5 pixels of 4 channels and 3 classes: every analytic
// derivative against a central difference of the loss.
TEST_CASE("cosine_classifier_loss: gradients match finite differences") {
  const int n = 5, dim = 4, classes = 3;
  RandomStream rng(stream_seed(7, "test.cosine_classifier"));
  std::vector<float> f = random_vector(n * dim, rng), w = random_vector(classes * dim, rng);
  const std::vector<int> labels{0, 2, 1, 1, 2};
  std::vector<float> gf(n * dim), gw(classes * dim, 0.f), scratch_f(n * dim), scratch_w(gw.size());
  const double loss = cosine_classifier_loss(f.data(), n, dim, labels.data(), w.data(), classes,
                                             10.0, gf.data(), gw.data());
  CHECK(loss > 0);
  auto eval = [&] {
    std::fill(scratch_w.begin(), scratch_w.end(), 0.f);
    return cosine_classifier_loss(f.data(), n, dim, labels.data(), w.data(), classes, 10.0,
                                  scratch_f.data(), scratch_w.data());
  };
  for (size_t k = 0; k < f.size(); ++k)
    CHECK(gf[k] == Approx(central(f, k, eval, 1e-3f)).margin(2e-3).epsilon(2e-2));
  for (size_t k = 0; k < w.size(); ++k)
    CHECK(gw[k] == Approx(central(w, k, eval, 1e-3f)).margin(2e-3).epsilon(2e-2));
}

// A feature along its class's row has cos = 1 there and -1 against the opposite row: the loss is
// log(1 + e^{-20}) ~ 2e-9 for tau = 10 and two classes.
TEST_CASE("cosine_classifier_loss: known value") {
  const std::vector<float> f{3, 0}, w{1, 0, -2, 0};
  const int label = 0;
  std::vector<float> gf(2), gw(4, 0.f);
  const double loss =
      cosine_classifier_loss(f.data(), 1, 2, &label, w.data(), 2, 10.0, gf.data(), gw.data());
  CHECK(loss == Approx(std::log1p(std::exp(-20.0))).epsilon(1e-6));
}

// Gaga's lift loss CE / ln(classes) with a bias: analytic against central differences.
TEST_CASE("linear_classifier_loss: gradients match finite differences") {
  const int n = 4, dim = 3, classes = 5;
  RandomStream rng(stream_seed(3, "test.linear_classifier"));
  std::vector<float> f = random_vector(n * dim, rng), w = random_vector(classes * dim, rng),
                     b = random_vector(classes, rng);
  const std::vector<int> labels{4, 0, 2, 2};
  std::vector<float> gf(n * dim), gw(classes * dim, 0.f), gb(classes, 0.f);
  linear_classifier_loss(f.data(), n, dim, labels.data(), w.data(), b.data(), classes, gf.data(),
                         gw.data(), gb.data());
  std::vector<float> sf(n * dim), sw(gw.size()), sb(classes);
  auto eval = [&] {
    return linear_classifier_loss(f.data(), n, dim, labels.data(), w.data(), b.data(), classes,
                                  sf.data(), sw.data(), sb.data());
  };
  for (size_t k = 0; k < f.size(); ++k)
    CHECK(gf[k] == Approx(central(f, k, eval, 1e-3f)).margin(1e-4).epsilon(1e-2));
  for (size_t k = 0; k < w.size(); ++k)
    CHECK(gw[k] == Approx(central(w, k, eval, 1e-3f)).margin(1e-4).epsilon(1e-2));
  for (size_t k = 0; k < b.size(); ++k)
    CHECK(gb[k] == Approx(central(b, k, eval, 1e-3f)).margin(1e-4).epsilon(1e-2));
}
