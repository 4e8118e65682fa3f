#include "nodes/features/contrastive_loss.hpp"

#include <cmath>
#include <vector>

#include "base/random.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

double loss_only(const std::vector<float>& in, const std::vector<float>& out, int dim,
                 double lambda) {
  std::vector<float> gi(in.size()), go(out.size());
  return mask_contrastive_loss(in.data(), int(in.size()) / dim, out.data(), int(out.size()) / dim,
                               dim, lambda, gi.data(), go.data());
}

}  // namespace

TEST_CASE("contrastive loss: hand-computed values", "[features]") {
  // Two inside pixels along +x: centroid (1, 0), inside cosines 1 -> inside term 0.
  // Outside: (0, 1) is orthogonal (0), (-1, 0) has cos -1 (hinged to 0), (1, 1) has cos 1/sqrt 2.
  const std::vector<float> in{1, 0, 3, 0};
  const std::vector<float> out{0, 1, -1, 0, 1, 1};
  CHECK(loss_only(in, out, 2, 0.2) == Approx(0.2 * (1.0 / std::sqrt(2.0)) / 3).epsilon(1e-6));
  // Inside pixels (1, 0) and (0, 1): centroid (0.5, 0.5), both at cos 1/sqrt 2.
  const std::vector<float> spread{1, 0, 0, 1};
  CHECK(loss_only(spread, {}, 2, 0.2) == Approx(1 - 1 / std::sqrt(2.0)).epsilon(1e-6));
  // Without outside pixels the repulsion term is absent whatever lambda is.
  CHECK(loss_only(spread, {}, 2, 5.0) == Approx(1 - 1 / std::sqrt(2.0)).epsilon(1e-6));
}

TEST_CASE("contrastive loss: gradient matches finite differences", "[features]") {
  const int dim = 4, n_in = 5, n_out = 6;
  RandomStream rng(7);
  auto normal = [&] { return static_cast<float>(rng.normal()); };
  std::vector<float> in(n_in * dim), out(n_out * dim);
  for (float& v : in) v = normal() + 0.8f;  // a common direction: a meaningful centroid
  for (float& v : out) v = normal();
  std::vector<float> gi(in.size()), go(out.size());
  const double lambda = 0.2;
  mask_contrastive_loss(in.data(), n_in, out.data(), n_out, dim, lambda, gi.data(), go.data());

  // The hinge max(0, cos) has a kink at 0: the data must keep every outside cosine away from it
  // for the central difference to be valid, and must have pixels on both sides of it.
  std::vector<double> centroid(dim, 0.0);
  for (int p = 0; p < n_in; ++p)
    for (int c = 0; c < dim; ++c) centroid[c] += in[p * dim + c] / n_in;
  int positive = 0;
  for (int p = 0; p < n_out; ++p) {
    double ab = 0, aa = 0, bb = 0;
    for (int c = 0; c < dim; ++c) {
      ab += centroid[c] * out[p * dim + c];
      aa += centroid[c] * centroid[c];
      bb += double(out[p * dim + c]) * out[p * dim + c];
    }
    const double cos = ab / std::sqrt(aa * bb);
    REQUIRE(std::abs(cos) > 0.02);
    positive += cos > 0;
  }
  REQUIRE(positive > 0);
  REQUIRE(positive < n_out);

  const float h = 1e-3f;
  auto check = [&](std::vector<float>& x, const std::vector<float>& analytic) {
    for (size_t k = 0; k < x.size(); ++k) {
      const float keep = x[k];
      x[k] = keep + h;
      const double up = loss_only(in, out, dim, lambda);
      x[k] = keep - h;
      const double down = loss_only(in, out, dim, lambda);
      x[k] = keep;
      CHECK(analytic[k] == Approx((up - down) / (2 * h)).margin(2e-4).epsilon(2e-3));
    }
  };
  check(in, gi);
  check(out, go);
}
