#include "nodes/inference/prototype_kmeans.hpp"

#include <vector>

#include "base/errors.hpp"
#include "nodes/inference/kmeans.hpp"

namespace gslift {

Eigen::MatrixXf spherical_kmeans(const Eigen::MatrixXf& points, int k, uint64_t seed,
                                 int max_iterations) {
  const Eigen::Index n = points.rows(), dim = points.cols();
  if (n == 0 || k < 1 || dim < 1) throw InputError("inference.kmeans: no prototypes to cluster");
  // The unit rows, row-major, for the shared K-means (kmeans.hpp) in its spherical form.
  std::vector<float> rows(size_t(n) * dim);
  for (Eigen::Index r = 0; r < n; ++r) {
    const float norm = points.row(r).norm();
    for (Eigen::Index c = 0; c < dim; ++c)
      rows[size_t(r) * dim + c] = norm > 0 ? points(r, c) / norm : points(r, c);
  }
  const KMeansResult result =
      kmeans(rows, static_cast<int>(dim), k, seed, max_iterations, /*spherical=*/true);
  Eigen::MatrixXf centres(result.k, dim);
  for (int c = 0; c < result.k; ++c)
    for (Eigen::Index d = 0; d < dim; ++d) centres(c, d) = result.centres[size_t(c) * dim + d];
  return centres;
}

}  // namespace gslift
