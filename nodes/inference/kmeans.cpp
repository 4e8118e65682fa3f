#include "nodes/inference/kmeans.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "base/random.hpp"

namespace gslift {
namespace {

double squared_distance(const float* a, const float* b, int dim) {
  double d = 0;
  for (int c = 0; c < dim; ++c) d += double(a[c] - b[c]) * double(a[c] - b[c]);
  return d;
}

}  // namespace

KMeansResult kmeans(const std::vector<float>& rows, int dim, int k, uint64_t seed,
                    int max_iterations, bool spherical) {
  if (dim < 1 || k < 1 || rows.size() < size_t(dim) || rows.size() % dim != 0)
    throw std::invalid_argument("kmeans: need at least one row of dim >= 1 values and k >= 1");
  const size_t n = rows.size() / dim;
  KMeansResult r;
  r.k = static_cast<int>(std::min<size_t>(k, n));
  r.centres.reserve(size_t(r.k) * dim);
  // k-means++: the first centre uniformly, each next one with probability proportional to the
  // squared distance to the nearest centre so far.
  RandomStream rng(stream_seed(seed, "kmeans"));
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  size_t pick = rng.below(n);
  for (int c = 0; c < r.k; ++c) {
    const float* centre = &rows[pick * dim];
    r.centres.insert(r.centres.end(), centre, centre + dim);
    double total = 0;
    for (size_t i = 0; i < n; ++i) {
      nearest[i] = std::min(nearest[i], squared_distance(&rows[i * dim], centre, dim));
      total += nearest[i];
    }
    if (total <= 0) {  // every row sits on a centre: fewer distinct rows than k
      r.k = c + 1;
      break;
    }
    double target = rng.uniform() * total;
    pick = n - 1;
    for (size_t i = 0; i < n; ++i) {
      target -= nearest[i];
      if (target < 0) {
        pick = i;
        break;
      }
    }
  }
  r.centres.resize(size_t(r.k) * dim);
  r.labels.assign(n, -1);
  std::vector<double> sums(size_t(r.k) * dim);
  std::vector<int> counts(r.k);
  for (r.iterations = 0; r.iterations < max_iterations; ++r.iterations) {
    bool changed = false;
    for (size_t i = 0; i < n; ++i) {
      int best = 0;
      double best_d = std::numeric_limits<double>::infinity();
      for (int c = 0; c < r.k; ++c) {
        const double d = squared_distance(&rows[i * dim], &r.centres[size_t(c) * dim], dim);
        if (d < best_d) best_d = d, best = c;
      }
      changed |= r.labels[i] != best;
      r.labels[i] = best;
    }
    if (!changed) break;
    std::fill(sums.begin(), sums.end(), 0.0);
    std::fill(counts.begin(), counts.end(), 0);
    for (size_t i = 0; i < n; ++i) {
      ++counts[r.labels[i]];
      for (int d = 0; d < dim; ++d) sums[size_t(r.labels[i]) * dim + d] += rows[i * dim + d];
    }
    for (int c = 0; c < r.k; ++c) {
      if (counts[c] == 0) continue;
      double norm = 0;
      for (int d = 0; d < dim; ++d) norm += sums[size_t(c) * dim + d] * sums[size_t(c) * dim + d];
      // Spherical: the mean direction; a centre whose rows cancel out keeps its place.
      if (spherical && !(norm > 0)) continue;
      const double scale = spherical ? 1 / std::sqrt(norm) : 1.0 / counts[c];
      for (int d = 0; d < dim; ++d)
        r.centres[size_t(c) * dim + d] = static_cast<float>(sums[size_t(c) * dim + d] * scale);
    }
  }
  return r;
}

}  // namespace gslift
