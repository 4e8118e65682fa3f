// One-to-one assignment maximising the total score of a rectangular matrix (rows <= cols or
// not), as scipy.optimize.linear_sum_assignment(M, maximize=True): the Hungarian method with
// potentials (Kuhn 1955, Munkres 1957; the O(n^2 m) shortest-augmenting-path form), on the
// matrix padded with zeros to square.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace gslift {

// match[r] = the column assigned to row r (every row gets a distinct column when rows <= cols;
// with more rows than columns, rows matched to padding get -1).
std::vector<int> max_score_assignment(const Eigen::MatrixXd& score);

}  // namespace gslift
