#include "nodes/eval/hungarian.hpp"

#include <algorithm>
#include <limits>

namespace gslift {

std::vector<int> max_score_assignment(const Eigen::MatrixXd& score) {
  const int rows = static_cast<int>(score.rows()), cols = static_cast<int>(score.cols());
  const int n = std::max(rows, cols);
  if (n == 0) return {};
  // Minimise cost = max - score on the zero-padded n x n matrix (padding scores 0).
  const double top = std::max(score.size() ? score.maxCoeff() : 0.0, 0.0);
  auto cost = [&](int r, int c) { return top - (r < rows && c < cols ? score(r, c) : 0.0); };
  const double inf = std::numeric_limits<double>::infinity();
  // 1-based potentials u (rows), v (cols); p[c] = row matched to column c (0 = none).
  std::vector<double> u(n + 1, 0), v(n + 1, 0);
  std::vector<int> p(n + 1, 0), way(n + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(n + 1, inf);
    std::vector<char> used(n + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double cur = cost(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= n; ++j) {
        if (used[j])
          u[p[j]] += delta, v[j] -= delta;
        else
          minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  std::vector<int> match(rows, -1);
  for (int j = 1; j <= n; ++j)
    if (p[j] - 1 < rows && j - 1 < cols) match[p[j] - 1] = j - 1;
  return match;
}

}  // namespace gslift
