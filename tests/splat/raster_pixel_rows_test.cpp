// Sampled-pixel rendering from the render cache and its adjoint (nodes/splat/pixel_rows.hpp).
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <tbb/global_control.h>

#include "nodes/splat/pixel_rows.hpp"
#include "nodes/splat/render_cache.hpp"
#include "tests/splat/raster_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

struct SampledCase {
  test::RasterScene scene = test::random_raster_scene(300, 0, 4, 21, 80, 48);
  RenderOutput forward = [this] {
    RenderSettings s;
    s.rgb = false;
    s.alpha = true;
    return render(scene.model, scene.camera, scene.pose, s);
  }();
  RenderCache cache{forward};
  std::vector<uint32_t> pixels;
  std::mt19937 rng{5};

  SampledCase() {
    // Repeats on purpose: a pixel drawn twice contributes twice to the adjoint.
    std::uniform_int_distribution<uint32_t> any(0, 80 * 48 - 1);
    for (int k = 0; k < 200; ++k) pixels.push_back(any(rng));
    pixels.push_back(pixels.front());
  }
  std::vector<float> random_values(size_t n) {
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::vector<float> v(n);
    for (float& x : v) x = u(rng);
    return v;
  }
};

}  // namespace

TEST_CASE("raster: sampled-pixel render equals the full cache render at those pixels",
          "[splat][raster]") {
  SampledCase c;
  const int C = 5;
  const std::vector<float> attributes = c.random_values(c.cache.gaussian_count() * C);
  const std::vector<float> full = c.cache.render(attributes, C);
  std::vector<float> sampled(c.pixels.size() * C);
  c.cache.render_pixels(attributes.data(), C, c.pixels, sampled.data());
  double err = 0, norm = 0;
  for (size_t k = 0; k < c.pixels.size(); ++k)
    for (int ch = 0; ch < C; ++ch) {
      err = std::max(err, double(std::abs(sampled[k * C + ch] - full[c.pixels[k] * C + ch])));
      norm = std::max(norm, double(std::abs(full[c.pixels[k] * C + ch])));
    }
  CHECK(norm > 0.1);
  CHECK(err < 1e-5);
}

TEST_CASE("raster: sampled-pixel backward is the adjoint, <R x, y> = <x, R^T y>",
          "[splat][raster]") {
  SampledCase c;
  const int C = 3;
  const size_t n = c.cache.gaussian_count();
  const std::vector<float> x = c.random_values(n * C);
  const std::vector<float> y = c.random_values(c.pixels.size() * C);
  std::vector<float> rx(c.pixels.size() * C);
  c.cache.render_pixels(x.data(), C, c.pixels, rx.data());
  std::vector<float> rty(n * C, 0.f);
  c.cache.backward_pixels(c.pixels, y.data(), C, rty.data());
  double lhs = 0, rhs = 0, scale = 0;
  for (size_t i = 0; i < rx.size(); ++i) lhs += double(rx[i]) * y[i];
  for (size_t i = 0; i < rty.size(); ++i) {
    rhs += double(x[i]) * rty[i];
    scale += std::abs(double(x[i]) * rty[i]);
  }
  CHECK(scale > 1);
  CHECK(std::abs(lhs - rhs) < 1e-5 * scale);
}

TEST_CASE("raster: sampled-pixel gradient matches finite differences of <R x, y>",
          "[splat][raster]") {
  SampledCase c;
  const int C = 2;
  const size_t n = c.cache.gaussian_count();
  std::vector<double> xd(n * C);
  const std::vector<float> x0 = c.random_values(n * C);
  const std::vector<float> y = c.random_values(c.pixels.size() * C);
  // f(x) = <R x, y>, evaluated in double from the float render.
  auto f = [&](const std::vector<float>& x) {
    std::vector<float> rx(c.pixels.size() * C);
    c.cache.render_pixels(x.data(), C, c.pixels, rx.data());
    double s = 0;
    for (size_t i = 0; i < rx.size(); ++i) s += double(rx[i]) * y[i];
    return s;
  };
  std::vector<float> grad(n * C, 0.f);
  c.cache.backward_pixels(c.pixels, y.data(), C, grad.data());
  int checked = 0;
  for (size_t i = 0; i < grad.size() && checked < 20; i += 7) {
    if (std::abs(grad[i]) < 1e-3f) continue;  // a Gaussian none of the samples sees
    const float h = 0.05f;
    std::vector<float> plus = x0, minus = x0;
    plus[i] += h;
    minus[i] -= h;
    const double fd = (f(plus) - f(minus)) / (2.0 * h);
    CHECK(std::abs(fd - grad[i]) < 2e-3 * std::max(1.0, std::abs(fd)));
    ++checked;
  }
  CHECK(checked >= 10);
}

TEST_CASE("raster: PixelRows keeps the render cache's pairs at or above min_weight, in its order",
          "[splat][raster]") {
  SampledCase c;
  // With no threshold, the cache's pixel rows bit for bit.
  const PixelRows all(c.forward);
  const auto& off = c.cache.pixel_offsets();
  CHECK(all.entries() == c.cache.entries());
  REQUIRE(all.pixel_count() == size_t(80 * 48));
  const PixelRowsView v = all.view();
  CHECK(std::equal(off.begin(), off.end(), v.offsets));
  CHECK(std::equal(c.cache.ids().begin(), c.cache.ids().end(), v.ids));
  CHECK(std::equal(c.cache.weights().begin(), c.cache.weights().end(), v.weights));

  const float min_weight = 0.05f;
  const PixelRows rows(c.forward, min_weight);
  CHECK(rows.pixel_count() == size_t(80 * 48));
  CHECK(rows.entries() < c.cache.entries());
  CHECK(rows.entries() > 0u);
  // One channel of ones: the sampled render is each pixel's sum of kept weights.
  const std::vector<float> ones(c.cache.gaussian_count(), 1.f);
  std::vector<float> sums(c.pixels.size());
  rows.render(ones.data(), 1, c.pixels, sums.data());
  for (size_t k = 0; k < c.pixels.size(); ++k) {
    double expected = 0;
    for (uint32_t e = off[c.pixels[k]]; e < off[c.pixels[k] + 1]; ++e)
      if (c.cache.weights()[e] >= min_weight) expected += c.cache.weights()[e];
    CHECK(std::abs(sums[k] - expected) < 1e-5);
  }
  // The same rows at one thread.
  std::vector<float> one_thread(c.pixels.size());
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    PixelRows(c.forward, min_weight).render(ones.data(), 1, c.pixels, one_thread.data());
  }
  CHECK(one_thread == sums);
}

// train_pixel_features sums the adjoint in blocks of Gaussian ids, one task each: the blocks
// together must give the whole pass's gradient bit for bit, each writing only its own rows.
TEST_CASE("raster: sampled-pixel backward over disjoint id ranges adds up to the whole pass",
          "[splat][raster]") {
  SampledCase c;
  const PixelRows rows(c.forward, 0.01f);
  const int C = 5;
  const size_t n = c.cache.gaussian_count();
  const std::vector<float> y = c.random_values(c.pixels.size() * C);
  std::vector<float> whole(n * C, 0.f);
  rows.backward(c.pixels, y.data(), C, whole.data());
  const uint32_t cuts[] = {0, uint32_t(n / 3), uint32_t(2 * n / 3), uint32_t(n)};
  std::vector<float> blocks(n * C, 0.f);
  for (int b = 0; b < 3; ++b) {
    std::vector<float> one(n * C, 0.f);
    rows.backward(c.pixels, y.data(), C, one.data(), cuts[b], cuts[b + 1]);
    size_t touched = 0;
    for (size_t i = 0; i < n * C; ++i) {
      const uint32_t id = uint32_t(i / C);
      if (id < cuts[b] || id >= cuts[b + 1]) {
        CHECK(one[i] == 0.f);  // not its row
      } else {
        touched += one[i] != 0.f;
        blocks[i] = one[i];
      }
    }
    CHECK(touched > 0u);  // every block has Gaussians the samples see
  }
  CHECK(blocks == whole);
}
