// SAGA v2 code's scale-gated variant: its loss gradient against finite differences, the mask
// scales on a hand-built plane, the quantile map, the smoothing's adjoint, and training on the
// two-group scene.
#include "nodes/features/scale_gated_features.hpp"

#include <cmath>

#include <tbb/global_control.h>
#include <Eigen/Core>

#include "base/random.hpp"
#include "nodes/features/feature_smoothing.hpp"
#include "nodes/features/mask_scales.hpp"
#include "nodes/features/scale_gated_loss.hpp"
#include "tests/features/two_groups.hpp"
#include "tests/pinhole.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("scale-gated loss gradient matches finite differences") {
  const int n = 10, d = 5, ns = 3;
  RandomStream rng(stream_seed(0, "test.scale_gated"));
  Eigen::MatrixXf f(n, d);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < d; ++c) f(i, c) = static_cast<float>(rng.normal(0, 1));
  std::vector<Eigen::MatrixXf> gt(ns, Eigen::MatrixXf::Zero(n, n));
  for (int k = 0; k < ns; ++k)
    for (int i = 0; i < n; ++i)
      for (int j = i; j < n; ++j) gt[k](i, j) = gt[k](j, i) = (i == j || rng.chance(0.4)) ? 1 : 0;
  const std::vector<float> scales = {0.1f, 0.5f, 0.9f};
  std::vector<float> area(n);
  for (float& a : area) a = static_cast<float>(rng.uniform(10, 500));
  const Eigen::MatrixXf w = scale_gated_pair_weights(area);
  CHECK(w.minCoeff() == Approx(1));
  CHECK(w.maxCoeff() == Approx(10));
  std::vector<float> gate(2 * d);
  for (float& g : gate) g = static_cast<float>(rng.uniform(-1, 1));
  const double rfn = 0.7;
  const ScaleGatedLoss l = scale_gated_loss(f, gt, scales, w, gate, rfn, 5);
  CHECK(l.positive_pairs > 0);
  CHECK(l.negative_pairs > 0);
  const float eps = 1e-3f;
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < d; ++c) {
      Eigen::MatrixXf a = f, b = f;
      a(i, c) += eps;
      b(i, c) -= eps;
      const double fd = (scale_gated_loss(a, gt, scales, w, gate, rfn, 5).loss -
                         scale_gated_loss(b, gt, scales, w, gate, rfn, 5).loss) /
                        (2 * eps);
      CHECK(l.grad_features(i, c) == Approx(fd).margin(2e-3));
    }
  for (int k = 0; k < 2 * d; ++k) {
    std::vector<float> a = gate, b = gate;
    a[k] += eps;
    b[k] -= eps;
    const double fd = (scale_gated_loss(f, gt, scales, w, a, rfn, 5).loss -
                       scale_gated_loss(f, gt, scales, w, b, rfn, 5).loss) /
                      (2 * eps);
    CHECK(l.grad_gate(k) == Approx(fd).margin(2e-3));
  }
}

TEST_CASE("mask scales of a fronto-parallel plane") {
  // Depth 2 everywhere; a 10 x 20 (rows x columns) rectangle mask; focal 50, centre (32, 24).
  const Camera cam = test::centred_pinhole(64, 48, 50);
  const std::vector<float> depth(64 * 48, 2.f);
  cv::Mat1b m = cv::Mat1b::zeros(48, 64);
  m(cv::Rect(10, 5, 20, 10)) = 255;
  // Erosion (3x3 sum >= 5 of 9) keeps the rectangle: its border pixels see 6 (edge) or 4
  // (corner) of 9, so the 4 corners go: 196 points.
  auto expected = [&](bool swap) {
    double n = 0, s[2] = {0, 0}, s2[2] = {0, 0};
    for (int y = 5; y < 15; ++y)
      for (int x = 10; x < 30; ++x) {
        if ((y == 5 || y == 14) && (x == 10 || x == 29)) continue;
        const double a = swap ? y : x, b = swap ? x : y;
        const double p[2] = {(a - 32) * 2 / 50.0, (b - 24) * 2 / 50.0};
        ++n;
        for (int k = 0; k < 2; ++k) s[k] += p[k], s2[k] += p[k] * p[k];
      }
    double v = 0;
    for (int k = 0; k < 2; ++k) v += 4 * (s2[k] - s[k] * s[k] / n) / (n - 1);
    return std::sqrt(v);
  };
  CHECK(mask_scales(depth, cam, {m}, false)[0] == Approx(expected(false)).epsilon(1e-5));
  // The plane is at constant depth: the swap changes nothing here (std is shift invariant).
  CHECK(mask_scales(depth, cam, {m}, true)[0] == Approx(expected(false)).epsilon(1e-5));
  cv::Mat1b dot = cv::Mat1b::zeros(48, 64);
  dot(10, 10) = 255;
  CHECK(mask_scales(depth, cam, {dot})[0] == 0.f);  // nothing left after erosion
}

TEST_CASE("quantile map as sklearn's uniform QuantileTransformer") {
  const QuantileMap q({5.f, 1.f, 3.f, 2.f, 4.f});
  CHECK(q(1.f) == Approx(0));
  CHECK(q(3.f) == Approx(0.5));
  CHECK(q(2.5f) == Approx(0.375));
  CHECK(q(5.f) == Approx(1));
  CHECK(q(9.f) == Approx(1));
  CHECK(q(-1.f) == Approx(0));
}

TEST_CASE("feature smoothing and its adjoint") {
  test::TwoGroups s = test::two_groups();
  const size_t n = s.model.size();
  const int dim = 3;
  const FeatureSmoothing smooth(s.model.means, 4);
  RandomStream rng(stream_seed(1, "test.smoothing"));
  std::vector<float> u(n * dim), g(n * dim), out(n * dim), back(n * dim, 0.f);
  for (float& x : u) x = static_cast<float>(rng.normal(0, 1));
  for (float& x : g) x = static_cast<float>(rng.normal(0, 1));
  const std::vector<int> slots = {0, 2};
  smooth.smooth(u.data(), dim, slots, out.data());
  smooth.backward(g.data(), dim, slots, back.data());
  double lhs = 0, rhs = 0;
  for (size_t i = 0; i < u.size(); ++i) lhs += double(out[i]) * g[i], rhs += double(u[i]) * back[i];
  CHECK(lhs == Approx(rhs).epsilon(1e-5));
  // Slot 0 is the Gaussian itself.
  const std::vector<int> self = {0};
  smooth.smooth(u.data(), dim, self, out.data());
  CHECK(out == u);
}

TEST_CASE("scale-gated features separate the masks' Gaussians, at any thread count") {
  test::TwoGroups s = test::two_groups();
  CorrespondenceOptions o;
  o.variant = AffinityVariant::ScaleGated;
  o.iterations = 120;
  o.dim = 8;
  o.lr = 2e-2;
  o.pixels_per_iteration = 96;
  o.smooth_k = 4;
  o.seed = 3;
  const CorrespondenceResult r = train_correspondence_features(s.model, s.capture, s.masks, o);
  CHECK(r.views == 2);
  CHECK(r.loss_end < r.loss_start);
  double within = 0, across = 0;
  int nw = 0, na = 0;
  for (size_t i = 0; i < s.group.size(); ++i)
    for (size_t j = i + 1; j < s.group.size(); ++j) {
      Eigen::Map<const Eigen::VectorXf> a(&r.model.features[i * 8], 8),
          b(&r.model.features[j * 8], 8);
      const double c = a.dot(b) / (a.norm() * b.norm());
      (s.group[i] == s.group[j] ? within : across) += c;
      (s.group[i] == s.group[j] ? nw : na) += 1;
    }
  CHECK(within / nw > 0.8);
  CHECK(across / na < 0.2);
  o.iterations = 10;
  std::vector<float> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = train_correspondence_features(s.model, s.capture, s.masks, o).model.features;
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = train_correspondence_features(s.model, s.capture, s.masks, o).model.features;
  }
  CHECK(one == two);
}
