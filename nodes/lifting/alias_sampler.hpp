// Walker's alias method (Walker 1977) with Vose's numerically stable construction (Vose 1991):
// O(n) setup, O(1) per draw from a discrete distribution. LangOR §1.3 draws the CVP pixels of all
// masks of all training views jointly from the Eq. 4 weights with it.
#pragma once

#include <cstdint>
#include <vector>

#include "base/random.hpp"

namespace gslift {

class AliasSampler {
 public:
  // Weights need not sum to 1; they must be finite and >= 0 with a positive sum (otherwise
  // std::invalid_argument). Entries of weight 0 are never drawn.
  explicit AliasSampler(const std::vector<double>& weights);

  // One index in [0, size()), with probability weight / sum(weights). Uses two draws of `rng`
  // (a column, then the coin that keeps it or takes its alias).
  int64_t sample(RandomStream& rng) const;

  // `count` draws from the stream stream_seed(seed, "alias.sample").
  std::vector<int64_t> sample(int64_t count, uint64_t seed) const;

  int64_t size() const { return static_cast<int64_t>(probability_.size()); }

 private:
  std::vector<double> probability_;  // chance to keep column i rather than take its alias
  std::vector<int64_t> alias_;
};

}  // namespace gslift
