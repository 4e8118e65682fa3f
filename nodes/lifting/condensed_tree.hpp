// The density half of HDBSCAN (McInnes et al.; Campello et al. 2013): condense the single-linkage
// tree with min_cluster_size, compute cluster stabilities, select flat clusters by excess of mass
// or leaves (with cluster_selection_epsilon, Malzer & Baum 2019), label points and give their
// membership probabilities. Follows Python hdbscan 0.8.33 (_hdbscan_tree.pyx) step for step,
// including row orders, so that results agree with it exactly.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "nodes/lifting/single_linkage.hpp"

namespace gslift {

// One row of the condensed tree: `child` (a point id < n, or a cluster id >= n; the root cluster
// is n) leaves or splits off `parent` at lambda = 1 / distance, with `child_size` points.
struct CondensedEdge {
  int64_t parent = 0;
  int64_t child = 0;
  double lambda = 0;
  int64_t child_size = 0;
};

// Walks the hierarchy breadth first from the top; a split where both sides have at least
// min_cluster_size points makes two new clusters, otherwise the small side's points fall out of
// the current cluster at that lambda (infinite for distance 0).
std::vector<CondensedEdge> condense_tree(const std::vector<LinkageMerge>& hierarchy,
                                         int64_t min_cluster_size);

enum class ClusterSelection {
  ExcessOfMass,  // "eom": the clusters maximising the total stability, none nested in another
  Leaf,          // "leaf": the leaves of the condensed cluster tree (finer, more homogeneous)
};

// Cannot-link constraints for the excess-of-mass selection, in the spirit of Campello et al.'s
// semi-supervised selection of clusters from the HDBSCAN hierarchy (FOSC, 2013): points carry a
// group id (e.g. the mask they were sampled from), and two groups of a pair are known to be
// different objects. A cluster "holds" a group when more than half of the group's points are in
// it; a cluster that holds both groups of a pair is not selected while its descendants can be,
// and excess of mass chooses among those instead. Empty = no constraints (plain HDBSCAN).
struct CannotLink {
  std::vector<int> point_groups;           // per point, -1 = in no group
  std::vector<std::pair<int, int>> pairs;  // group ids, each in [0, number of groups)
  bool empty() const { return pairs.empty(); }
};

struct FlatClusteringOptions {
  ClusterSelection selection = ClusterSelection::ExcessOfMass;
  // Clusters born (split off) at a distance below this are merged upwards until their parent was
  // born above it; 0 disables. Distances are in the metric's units.
  double cluster_selection_epsilon = 0.0;
  // Whether the root (all points) may be the one selected cluster; false gives >= 2 clusters or
  // none. When the root is selected, only the points that stay until its densest level (lambda
  // >= the largest lambda of its own rows, or >= 1 / epsilon when epsilon is set) are labelled,
  // as in Python hdbscan (and scikit-learn); the others are noise.
  bool allow_single_cluster = false;
  // Campello et al.'s reference code: a point joins its cluster only if it left it after the
  // cluster was born (strictly larger lambda); the min_samples / min_cluster_size shifts of that
  // convention are applied by hdbscan() (hdbscan.hpp).
  bool match_reference_implementation = false;
  // Excess of mass only (leaf selection never merges): see CannotLink.
  CannotLink cannot_link;
};

struct FlatClustering {
  std::vector<int> labels;  // per point: 0 .. clusters - 1 (ascending cluster id), -1 noise
  std::vector<double> probabilities;  // per point: membership strength in [0, 1]; 0 for noise
  int clusters = 0;
};

FlatClustering extract_clusters(const std::vector<CondensedEdge>& tree, int64_t num_points,
                                const FlatClusteringOptions& options);

}  // namespace gslift
