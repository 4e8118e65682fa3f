// A small, portable random stream for the generator. std::normal_distribution and friends are
// implementation-defined, so the same seed would give different captures on different standard
// libraries; this stream is fully specified (SplitMix64 + Box-Muller) and therefore gives
// byte-identical captures everywhere. Streams are keyed by (seed, purpose, index), never by thread.
#pragma once

#include <cmath>
#include <cstdint>

namespace gslift::synth {

// SplitMix64 finaliser: a strong 64-bit mix used both to seed streams and to hash coordinates.
inline uint64_t mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Seed of an independent stream for (seed, purpose, index), e.g. (capture seed, "vlm", view).
inline uint64_t stream_seed(uint64_t seed, uint64_t purpose, uint64_t index = 0) {
  return mix64(mix64(mix64(seed) ^ purpose) ^ index);
}

class RandomStream {
 public:
  explicit RandomStream(uint64_t seed) : state_(seed) {}

  uint64_t next() { return mix64(state_++); }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n).
  int below(int n) { return static_cast<int>(uniform() * n); }
  bool chance(double p) { return uniform() < p; }
  // Standard normal (Box-Muller; one value per call keeps the stream simple to reason about).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  double normal(double mean, double sigma) { return mean + sigma * normal(); }
  // Poisson(lambda) by Knuth's product method: fine for the small rates used here.
  int poisson(double lambda) {
    const double limit = std::exp(-lambda);
    int k = 0;
    for (double p = uniform(); p > limit; p *= uniform()) ++k;
    return k;
  }

 private:
  uint64_t state_;
};

// Purposes for stream_seed: one constant per consumer so that adding a consumer never shifts the
// random numbers another one sees.
enum StreamPurpose : uint64_t {
  kLayoutStream = 1,
  kCameraStream,
  kVlmStream,
  kSamBoxStream,
  kSamAutoStream,
  kDepthPriorStream,
  kPoseNoiseStream,
  kSparsePointStream,
};

}  // namespace gslift::synth
