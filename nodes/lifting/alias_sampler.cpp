#include "nodes/lifting/alias_sampler.hpp"

#include <cmath>
#include <stdexcept>

namespace gslift {

AliasSampler::AliasSampler(const std::vector<double>& weights) {
  const int64_t n = static_cast<int64_t>(weights.size());
  double total = 0;
  for (const double w : weights) {
    if (!std::isfinite(w) || w < 0)
      throw std::invalid_argument("AliasSampler: weights must be finite and non-negative");
    total += w;
  }
  if (!(total > 0)) throw std::invalid_argument("AliasSampler: the weights sum to zero");

  // Vose: scale to mean 1, pair each under-full column with an over-full donor.
  probability_.assign(n, 0.0);
  alias_.assign(n, 0);
  std::vector<double> scaled(n);
  std::vector<int64_t> small, large;
  for (int64_t i = 0; i < n; ++i) {
    scaled[i] = weights[i] * static_cast<double>(n) / total;
    (scaled[i] < 1.0 ? small : large).push_back(i);
  }
  while (!small.empty() && !large.empty()) {
    const int64_t s = small.back(), l = large.back();
    small.pop_back();
    probability_[s] = scaled[s];
    alias_[s] = l;
    scaled[l] = (scaled[l] + scaled[s]) - 1.0;
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // What remains is full up to rounding. A zero-weight column can only remain through rounding
  // too; it then defers to the first drawable column so that it is never drawn.
  int64_t first_positive = 0;
  while (weights[first_positive] == 0) ++first_positive;
  for (const int64_t l : large) probability_[l] = 1.0;
  for (const int64_t s : small) {
    probability_[s] = weights[s] > 0 ? 1.0 : 0.0;
    if (weights[s] == 0) alias_[s] = first_positive;
  }
}

int64_t AliasSampler::sample(RandomStream& rng) const {
  const int64_t i = rng.below(size());
  return rng.uniform() < probability_[i] ? i : alias_[i];
}

std::vector<int64_t> AliasSampler::sample(int64_t count, uint64_t seed) const {
  RandomStream rng(stream_seed(seed, "alias.sample"));
  std::vector<int64_t> out(count);
  for (auto& x : out) x = sample(rng);
  return out;
}

}  // namespace gslift
