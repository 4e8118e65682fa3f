#include "nodes/lifting/single_linkage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "nodes/lifting/numpy_argsort.hpp"

namespace gslift {
namespace {

// Squared norms in the order of NumPy's SSE2 einsum, which scikit-learn's row_norms uses: two
// lanes (even and odd coordinates); blocks of 8 coordinates are accumulated last pair first, the
// rest pair by pair; the result is lane 0 + lane 1.
std::vector<double> squared_norms(const PointMatrix& points) {
  const int64_t d = points.cols();
  std::vector<double> norms(points.rows());
  for (int64_t i = 0; i < points.rows(); ++i) {
    const double* x = points.row(i).data();
    double lane[2] = {0, 0};
    int64_t k = 0;
    for (; k + 8 <= d; k += 8)
      for (int pair = 3; pair >= 0; --pair)
        for (int l = 0; l < 2; ++l) lane[l] += x[k + 2 * pair + l] * x[k + 2 * pair + l];
    for (; k < d; ++k) lane[k % 2] += x[k] * x[k];
    norms[i] = lane[0] + lane[1];
  }
  return norms;
}

// Euclidean distance as scikit-learn's euclidean_distances computes it (which Python hdbscan's
// generic algorithm uses): sqrt(max(0, (-2 a.b + |a|^2) + |b|^2)), zero on the diagonal. Its
// rounding decides which of two mathematically equal distances is smaller, so computing it the
// same way (same operations, same order) is what makes tied data (iris, digits) partition exactly
// as the reference. The price is cancellation for points far from the origin relative to their
// spread (relative error ~ 1e-16 |a|^2 / d^2): centre such data first. The file is compiled
// with -ffp-contract=off (CMakeLists.txt): numpy never fuses a multiply and an add.
class Distance {
 public:
  explicit Distance(const PointMatrix& points) : points_(points), norms_(squared_norms(points)) {}

  // Row a, column b of the (slightly asymmetric) distance matrix.
  double operator()(int64_t a, int64_t b) const { return std::sqrt(squared(a, b)); }

  // Its square, before the square root (monotone, so order statistics can skip the root).
  double squared(int64_t a, int64_t b) const {
    if (a == b) return 0.0;
    const double* pa = points_.row(a).data();
    const double* pb = points_.row(b).data();
    double dot = 0;
    for (int64_t k = 0; k < points_.cols(); ++k) dot += pa[k] * pb[k];
    double squared = -2 * dot;
    squared += norms_[a];
    squared += norms_[b];
    return std::max(squared, 0.0);
  }

 private:
  const PointMatrix& points_;
  std::vector<double> norms_;
};

// The closest vertex outside the tree so far; ties go to the lowest index, like np.argmin over
// the remaining vertices in index order.
struct Closest {
  double distance = std::numeric_limits<double>::infinity();
  int64_t index = -1;

  void offer(double d, int64_t i) {
    if (index < 0 || d < distance || (d == distance && i < index)) {
      distance = d;
      index = i;
    }
  }
};

}  // namespace

std::vector<double> core_distances(const PointMatrix& points, int k) {
  const int64_t n = points.rows();
  if (k < 1 || k >= n) throw std::invalid_argument("core_distances: k must be in [1, n - 1]");
  std::vector<double> core(n);
  const Distance distance(points);
  tbb::parallel_for(
      tbb::blocked_range<int64_t>(0, n, 64), [&](const tbb::blocked_range<int64_t>& r) {
        // The k + 1 smallest squared entries of column i (column i of the distance matrix is what
        // np.partition(D, k, axis=0) reads), kept sorted; most entries fail the first comparison,
        // which makes this several times faster than nth_element over the whole column. The square
        // root is monotone, so the root of the k-th smallest square is the k-th smallest distance.
        std::vector<double> smallest(k + 1);
        for (int64_t i = r.begin(); i != r.end(); ++i) {
          std::fill(smallest.begin(), smallest.end(), std::numeric_limits<double>::infinity());
          for (int64_t j = 0; j < n; ++j) {
            const double d = distance.squared(j, i);
            if (!(d < smallest[k])) continue;
            int pos = k;
            while (pos > 0 && smallest[pos - 1] > d) {
              smallest[pos] = smallest[pos - 1];
              --pos;
            }
            smallest[pos] = d;
          }
          core[i] = std::sqrt(smallest[k]);
        }
      });
  return core;
}

std::vector<PrimEdge> mutual_reachability_mst(const PointMatrix& points,
                                              const std::vector<double>& core) {
  const int64_t n = points.rows();
  std::vector<PrimEdge> edges;
  if (n < 2) return edges;
  edges.reserve(n - 1);
  std::vector<char> in_tree(n, 0);
  std::vector<double> to_tree(n, std::numeric_limits<double>::infinity());
  const Distance distance(points);
  int64_t current = 0;
  in_tree[0] = 1;
  for (int64_t step = 1; step < n; ++step) {
    const Closest closest = tbb::parallel_reduce(
        tbb::blocked_range<int64_t>(0, n, 1024), Closest{},
        [&](const tbb::blocked_range<int64_t>& r, Closest best) {
          for (int64_t j = r.begin(); j != r.end(); ++j) {
            if (in_tree[j]) continue;
            const double mr = std::max({core[current], core[j], distance(current, j)});
            to_tree[j] = std::min(to_tree[j], mr);
            best.offer(to_tree[j], j);
          }
          return best;
        },
        [](Closest a, const Closest& b) {
          if (b.index >= 0) a.offer(b.distance, b.index);
          return a;
        });
    edges.push_back({current, closest.index, closest.distance});
    in_tree[closest.index] = 1;
    current = closest.index;
  }
  return edges;
}

std::vector<LinkageMerge> single_linkage(const std::vector<PrimEdge>& edges) {
  const int64_t n = static_cast<int64_t>(edges.size()) + 1;
  std::vector<double> weights(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) weights[i] = edges[i].weight;
  const std::vector<int64_t> order = numpy_argsort(weights);

  // Union-find over points and merge clusters (ids n .. 2n - 2); each merge gets a fresh root.
  std::vector<int64_t> parent(2 * n - 1, -1);
  std::vector<int64_t> size(2 * n - 1, 0);
  std::fill(size.begin(), size.begin() + n, 1);
  auto find = [&](int64_t x) {
    int64_t root = x;
    while (parent[root] != -1) root = parent[root];
    while (x != root) {
      const int64_t next = parent[x];
      parent[x] = root;
      x = next;
    }
    return root;
  };

  std::vector<LinkageMerge> merges;
  merges.reserve(edges.size());
  int64_t next_label = n;
  for (const int64_t e : order) {
    const int64_t a = find(edges[e].from);
    const int64_t b = find(edges[e].to);
    size[next_label] = size[a] + size[b];
    parent[a] = next_label;
    parent[b] = next_label;
    merges.push_back({a, b, edges[e].weight, size[next_label]});
    ++next_label;
  }
  return merges;
}

}  // namespace gslift
