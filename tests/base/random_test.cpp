// The portable random stream: exact first values (computed independently from the SplitMix64
// definition, in Python's integers and IEEE doubles), ranges, moments, and independence from the
// thread count.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "base/random.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("the stream of a seed is splitmix64(seed), splitmix64(seed + 1), ...", "[random]") {
  RandomStream rng(42);
  CHECK(rng.next() == 0xbdd732262feb6e95ull);
  CHECK(rng.next() == 0xba69ec90eb4fef88ull);
  CHECK(rng.next() == 0xfb452912299a5453ull);
  RandomStream again(42);
  for (uint64_t k = 0; k < 3; ++k) CHECK(again.next() == splitmix64(42 + k));
}

TEST_CASE("first uniforms, integers, normals and a shuffle of seed 42", "[random]") {
  RandomStream u(42);
  CHECK(u.uniform() == 0.7415648787718233);  // (0xbdd732262feb6e95 >> 11) / 2^53
  CHECK(u.uniform() == 0.7281787732893573);
  CHECK(u.uniform() == 0.9815240544645374);

  RandomStream b(42);
  std::vector<int> drawn;
  for (int k = 0; k < 8; ++k) drawn.push_back(b.below(10));
  CHECK(drawn == std::vector<int>{7, 7, 9, 9, 7, 4, 0, 1});

  // Box-Muller: sqrt(-2 ln(1 - u1)) cos(2 pi u2) over consecutive uniform pairs.
  RandomStream n(42);
  CHECK(n.normal() == Approx(-0.22484288910662664).epsilon(1e-14));
  CHECK(n.normal() == Approx(2.7698849788498263).epsilon(1e-14));
  CHECK(n.normal() == Approx(-1.6096886419057537).epsilon(1e-14));

  RandomStream s(42);
  std::vector<int> order{0, 1, 2, 3, 4, 5};
  s.shuffle(order.begin(), order.end());
  CHECK(order == std::vector<int>{0, 1, 2, 5, 3, 4});
}

TEST_CASE("stream seeds are fixed numbers, and a named purpose is its FNV-1a hash", "[random]") {
  CHECK(stream_seed(1, 2, 3) == 0xd0734750fde362b3ull);
  CHECK(stream_seed(7, "densify.split", 5) == 0xb7d8c125ce2365e5ull);
  CHECK(stream_seed(7, "densify.split", 5) == stream_seed(7, fnv1a64("densify.split"), 5));
  CHECK(stream_seed(1, 2) == stream_seed(1, 2, 0));
  CHECK(stream_seed(1, 2, 3) != stream_seed(1, 2, 4));
  CHECK(stream_seed(1, 2, 3) != stream_seed(1, 3, 3));
  CHECK(stream_seed(1, 2, 3) != stream_seed(2, 2, 3));
}

TEST_CASE("uniform() lies in 0 <= u < 1 and reaches both ends of its 53-bit grid", "[random]") {
  // splitmix64 is a bijection: these seeds (found by inverting it) make the first draw all ones
  // and all zeros.
  REQUIRE(splitmix64(0x31628af67b2131abull) == ~0ull);
  REQUIRE(splitmix64(0x61c8864680b583ebull) == 0ull);
  CHECK(RandomStream(0x31628af67b2131abull).uniform() == 1.0 - std::ldexp(1.0, -53));
  CHECK(RandomStream(0x61c8864680b583ebull).uniform() == 0.0);
  CHECK(std::isfinite(RandomStream(0x61c8864680b583ebull).normal()));  // log(1 - 0) is finite

  RandomStream rng(stream_seed(3, "uniform"));
  const int n = 200000;
  double sum = 0, sum2 = 0, lo = 1, hi = 0;
  for (int k = 0; k < n; ++k) {
    const double x = rng.uniform();
    sum += x;
    sum2 += x * x;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  CHECK(lo >= 0.0);
  CHECK(hi < 1.0);
  const double mean = sum / n, var = sum2 / n - mean * mean;
  // Standard errors: sqrt(1/12 / n) = 6.5e-4 for the mean; about 3e-4 for the variance.
  CHECK(std::abs(mean - 0.5) < 4 * 6.5e-4);
  CHECK(std::abs(var - 1.0 / 12) < 4 * 3e-4);

  RandomStream r(stream_seed(3, "interval"));
  for (int k = 0; k < 1000; ++k) {
    const double x = r.uniform(-2.0, 5.0);
    CHECK((x >= -2.0 && x < 5.0));
  }
}

TEST_CASE("below(n) lies in 0 <= k < n and hits every value about equally often", "[random]") {
  RandomStream rng(stream_seed(4, "below"));
  for (int k = 0; k < 100; ++k) CHECK(rng.below(1) == 0);
  for (int k = 0; k < 1000; ++k) {
    const size_t big = rng.below(size_t(1) << 40);
    CHECK(big < (size_t(1) << 40));
    const int64_t wide = rng.below(int64_t(3));
    CHECK((wide >= 0 && wide < 3));
  }
  const int n = 7, draws = 140000;
  std::vector<int> count(n, 0);
  for (int k = 0; k < draws; ++k) {
    const int x = rng.below(n);
    REQUIRE((x >= 0 && x < n));
    ++count[x];
  }
  // Each count is Binomial(140000, 1/7): mean 20000, standard deviation 131.
  for (int c : count) CHECK(std::abs(c - draws / n) < 4 * 131);
}

TEST_CASE("normal() has mean 0 and variance 1, normal(m, s) scales it", "[random]") {
  RandomStream rng(stream_seed(5, "normal"));
  const int n = 200000;
  double sum = 0, sum2 = 0, sum4 = 0;
  for (int k = 0; k < n; ++k) {
    const double x = rng.normal();
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
  }
  // Standard errors: 1/sqrt(n) = 2.2e-3 (mean), sqrt(2/n) = 3.2e-3 (variance), sqrt(96/n) =
  // 0.022 (fourth moment, 3 for a normal: checks the shape, not only the first two moments).
  CHECK(std::abs(sum / n) < 4 * 2.2e-3);
  CHECK(std::abs(sum2 / n - 1) < 4 * 3.2e-3);
  CHECK(std::abs(sum4 / n - 3) < 4 * 0.022);

  RandomStream a(9), b(9);
  for (int k = 0; k < 10; ++k) CHECK(a.normal(2.0, 0.5) == 2.0 + 0.5 * b.normal());
}

TEST_CASE("chance(p) and poisson(lambda) have the right rates", "[random]") {
  RandomStream rng(stream_seed(6, "counts"));
  const int n = 100000;
  int hits = 0;
  long total = 0;
  for (int k = 0; k < n; ++k) {
    hits += rng.chance(0.3);
    total += rng.poisson(2.5);
  }
  // Standard errors: sqrt(0.21 n) = 145 hits; sqrt(2.5 / n) = 5e-3 on the Poisson mean.
  CHECK(std::abs(hits - 0.3 * n) < 4 * 145);
  CHECK(std::abs(double(total) / n - 2.5) < 4 * 5e-3);
  CHECK(rng.poisson(0.0) == 0);
}

TEST_CASE("shuffle() gives a permutation, each of the 3! orders equally often", "[random]") {
  RandomStream rng(stream_seed(7, "shuffle"));
  std::vector<int> big(1000);
  std::iota(big.begin(), big.end(), 0);
  rng.shuffle(big.begin(), big.end());
  std::vector<int> sorted = big;
  std::sort(sorted.begin(), sorted.end());
  CHECK(sorted[0] == 0);
  CHECK(sorted[999] == 999);
  CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());

  std::vector<int> none;
  rng.shuffle(none.begin(), none.end());  // empty and single ranges are left alone
  const int draws = 60000;
  std::vector<int> count(9 * 3, 0);  // indexed by 9 a + 3 b + c
  for (int k = 0; k < draws; ++k) {
    int v[3] = {0, 1, 2};
    rng.shuffle(v, v + 3);
    ++count[9 * v[0] + 3 * v[1] + v[2]];
  }
  int seen = 0;
  // Each order is Binomial(60000, 1/6): mean 10000, standard deviation 91.
  for (int c : count)
    if (c) {
      ++seen;
      CHECK(std::abs(c - draws / 6) < 4 * 91);
    }
  CHECK(seen == 6);
}

TEST_CASE("streams keyed by index draw the same numbers at any thread count", "[random]") {
  auto draw_all = [](int threads) {
    std::vector<double> out(4096);
    tbb::task_arena arena(threads);
    arena.execute([&] {
      tbb::parallel_for(size_t(0), out.size(), [&](size_t i) {
        RandomStream rng(stream_seed(11, "pieces", i));
        const double z = rng.normal();
        out[i] = z + rng.below(100);
      });
    });
    return out;
  };
  const std::vector<double> one = draw_all(1);
  CHECK(draw_all(2) == one);
  RandomStream first(stream_seed(11, "pieces", 0));
  const double z = first.normal();
  CHECK(one[0] == z + first.below(100));
}
