// The generator's random streams (base/random.hpp), one purpose per consumer: every simulator
// draws from stream_seed(capture seed, purpose, index), never from a thread, so captures are
// byte-identical at any thread count and on any standard library.
#pragma once

#include <cstdint>

#include "base/random.hpp"

namespace gslift::synth {

// One constant per consumer, so that adding a consumer never shifts the random numbers another
// one sees.
enum StreamPurpose : uint64_t {
  kLayoutStream = 1,
  kCameraStream,
  kVlmStream,
  kSamBoxStream,
  kSamAutoStream,
  kDepthPriorStream,
  kPoseNoiseStream,
  kSparsePointStream,
  kDrapeStream,
};

}  // namespace gslift::synth
