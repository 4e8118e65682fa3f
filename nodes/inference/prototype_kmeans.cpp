#include "nodes/inference/prototype_kmeans.hpp"

#include <algorithm>
#include <vector>

#include "base/errors.hpp"
#include "base/random.hpp"

namespace gslift {

Eigen::MatrixXf spherical_kmeans(const Eigen::MatrixXf& points, int k, uint64_t seed,
                                 int max_iterations) {
  const Eigen::Index n = points.rows();
  if (n == 0 || k < 1) throw InputError("inference.kmeans: no prototypes to cluster");
  k = static_cast<int>(std::min<Eigen::Index>(k, n));
  Eigen::MatrixXf x = points;
  for (Eigen::Index r = 0; r < n; ++r)
    if (x.row(r).norm() > 0) x.row(r).normalize();

  // k-means++: the first centre uniform, then each with probability ~ squared distance to the
  // nearest centre chosen so far (1 - cos, times 2, for unit vectors).
  RandomStream rng(stream_seed(seed, "kmeans.init"));
  Eigen::MatrixXf centres(k, x.cols());
  centres.row(0) = x.row(rng.below(n));
  std::vector<double> d2(n);
  for (Eigen::Index r = 0; r < n; ++r) d2[r] = (x.row(r) - centres.row(0)).squaredNorm();
  for (int c = 1; c < k; ++c) {
    double total = 0;
    for (double d : d2) total += d;
    Eigen::Index pick = n - 1;
    if (total > 0) {
      double u = rng.uniform() * total;
      for (Eigen::Index r = 0; r < n; ++r)
        if ((u -= d2[r]) < 0) {
          pick = r;
          break;
        }
    } else {
      pick = rng.below(n);
    }
    centres.row(c) = x.row(pick);
    for (Eigen::Index r = 0; r < n; ++r)
      d2[r] = std::min<double>(d2[r], (x.row(r) - centres.row(c)).squaredNorm());
  }

  std::vector<int> assign(n, -1);
  for (int it = 0; it < max_iterations; ++it) {
    bool changed = false;
    for (Eigen::Index r = 0; r < n; ++r) {
      Eigen::Index best = 0;
      (centres * x.row(r).transpose()).maxCoeff(&best);
      if (assign[r] != best) changed = true, assign[r] = static_cast<int>(best);
    }
    if (!changed) break;
    Eigen::MatrixXf sums = Eigen::MatrixXf::Zero(k, x.cols());
    for (Eigen::Index r = 0; r < n; ++r) sums.row(assign[r]) += x.row(r);
    for (int c = 0; c < k; ++c)
      if (sums.row(c).norm() > 0) centres.row(c) = sums.row(c).normalized();  // else kept
  }
  return centres;
}

}  // namespace gslift
