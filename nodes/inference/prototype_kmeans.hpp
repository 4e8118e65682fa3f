// Proto-SaGa Table 4's K-means baseline: instead of averaging the per-view prototypes v_k(t) by
// their consistent label (Eq. 18), cluster them with K-means, k = the number of labels, and use
// the cluster centres as the classifier (argmax cosine, as Eq. 19). Spherical K-means (rows
// L2-normalised, centres renormalised) because the classifier compares directions: the shared
// K-means of kmeans.hpp (k-means++ seeding, Lloyd steps) in its spherical form.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace gslift {

// Unit-norm centres (k x dim) of the rows of `points`; k is clamped to the number of distinct
// rows.
Eigen::MatrixXf spherical_kmeans(const Eigen::MatrixXf& points, int k, uint64_t seed,
                                 int max_iterations = 100);

}  // namespace gslift
