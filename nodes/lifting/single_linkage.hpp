// The geometric half of HDBSCAN (Campello et al. 2013, McInnes et al. 2017): core distances, the
// minimum spanning tree of the mutual-reachability graph, and the single-linkage hierarchy built
// from it. Distances are computed on the fly (O(n d) memory), so the cost is O(n^2 d) time.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace gslift {

// Points as rows.
using PointMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Core distance of each point: the Euclidean distance (computed as scikit-learn does, see
// single_linkage.cpp) to its k-th nearest neighbour, where the
// point itself is the 0-th (distance 0) and so is NOT counted; duplicates of the point count as
// neighbours at distance 0 (Python hdbscan, np.partition(D, k, axis=0)[k]). Requires 1 <= k < n.
std::vector<double> core_distances(const PointMatrix& points, int k);

// One edge of Prim's tree as Python hdbscan's mst_linkage_core emits it: `from` is the vertex
// added in the previous step (not necessarily the tree neighbour of `to`), `weight` the
// mutual-reachability distance at which `to` joined. Sorted by weight, this sequence gives the
// same single-linkage hierarchy as the true tree edges (Müllner 2011, "MST-linkage-core").
struct PrimEdge {
  int64_t from = 0;
  int64_t to = 0;
  double weight = 0;
};

// Prim's algorithm on the dense mutual-reachability graph d_mr(a, b) = max(core(a), core(b),
// d(a, b)), starting at point 0; the next vertex is the lowest index among the closest. The
// distance updates of each step run in parallel (tbb::parallel_reduce with an index tie-break,
// so the result does not depend on the thread count).
std::vector<PrimEdge> mutual_reachability_mst(const PointMatrix& points,
                                              const std::vector<double>& core);

// One merge of the single-linkage tree in SciPy's linkage format: clusters `left` and `right`
// (ids < n are points, id n + i is the cluster made by merge i) join at `distance` into a cluster
// of `size` points.
struct LinkageMerge {
  int64_t left = 0;
  int64_t right = 0;
  double distance = 0;
  int64_t size = 0;
};

// Sorts the edges by weight (in NumPy's argsort order, see numpy_argsort.hpp) and merges them
// with a union-find, as Python hdbscan's label(); n - 1 merges for n points.
std::vector<LinkageMerge> single_linkage(const std::vector<PrimEdge>& edges);

}  // namespace gslift
