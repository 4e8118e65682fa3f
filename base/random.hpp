// The project's one random stream. std::mt19937 is specified, but std::uniform_int_distribution,
// std::normal_distribution and std::shuffle are not (libstdc++, libc++ and MSVC draw different
// numbers from the same engine), so a seed would give different results on different standard
// libraries. This stream is specified here down to the bit: SplitMix64 (Steele, Lea, Flood 2014)
// for the bits, 53-bit uniforms, Box-Muller normals, Knuth's Poisson and a Fisher-Yates shuffle.
//
// A stream is keyed by what it is for, never by a thread: seed it with stream_seed(seed, purpose,
// index) where index numbers the independent pieces of work (a view, a mask, a parent Gaussian),
// so a parallel loop draws the same numbers at any thread count.
#pragma once

#include <cmath>
#include <cstdint>
#include <iterator>
#include <string_view>
#include <type_traits>
#include <utility>

#include "base/hash.hpp"

namespace gslift {

// Seed of an independent stream for (seed, purpose, index), e.g. (capture seed, VLM, view).
inline uint64_t stream_seed(uint64_t seed, uint64_t purpose, uint64_t index = 0) {
  return splitmix64(splitmix64(splitmix64(seed) ^ purpose) ^ index);
}

// The same with a purpose named by text ("densify.split"), hashed with FNV-1a.
inline uint64_t stream_seed(uint64_t seed, std::string_view purpose, uint64_t index = 0) {
  return stream_seed(seed, fnv1a64(purpose), index);
}

class RandomStream {
 public:
  // The stream is splitmix64(seed), splitmix64(seed + 1), ...: the streams of seeds s and s + 1
  // overlap shifted by one draw, so seed it with stream_seed(), not with consecutive numbers.
  explicit RandomStream(uint64_t seed) : state_(seed) {}

  uint64_t next() { return splitmix64(state_++); }

  // Uniform in [0, 1): the top 53 bits of a draw over 2^53, so every value is a multiple of 2^-53.
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  // Uniform integer in [0, n) for 0 < n < 2^53, as floor(uniform() * n) (one draw). Each value
  // has probability 1/n to within 1/2^53, the same order as the modulo method's bias, which
  // is invisible at the sizes used here (pixels, views, Gaussians).
  template <class Int>
  Int below(Int n) {
    static_assert(std::is_integral_v<Int>, "below() takes an integer count");
    return static_cast<Int>(uniform() * static_cast<double>(n));
  }

  bool chance(double p) { return uniform() < p; }

  // Standard normal by Box-Muller (Box, Muller 1958); one value per call (two uniforms) keeps
  // the stream simple to reason about.
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]: log(u1) is finite
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  double normal(double mean, double sigma) { return mean + sigma * normal(); }

  // Poisson(lambda) by Knuth's product method (TAOCP vol. 2, 3.4.1): O(lambda) draws, meant for
  // small rates.
  int poisson(double lambda) {
    const double limit = std::exp(-lambda);
    int k = 0;
    for (double p = uniform(); p > limit; p *= uniform()) ++k;
    return k;
  }

  // Uniform random permutation of [first, last) by Fisher-Yates (Durstenfeld's in-place form):
  // from the back, swap each element with one drawn from those up to it.
  template <class RandomIt>
  void shuffle(RandomIt first, RandomIt last) {
    using Diff = typename std::iterator_traits<RandomIt>::difference_type;
    for (Diff i = last - first; i > 1; --i) std::swap(first[i - 1], first[below(i)]);
  }

 private:
  uint64_t state_;
};

}  // namespace gslift
