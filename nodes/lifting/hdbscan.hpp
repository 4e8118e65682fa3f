// HDBSCAN (McInnes, Healy & Astels 2017; Campello, Moulavi & Sander 2013; docs/references.md): the
// density-based clustering that LangOR's CVP lifting (Eq. 4-5) and the mask-level baseline use.
//
// Conventions (they decide whether results match other implementations):
// - min_samples follows Python hdbscan's default: the core distance is the distance to the
//   min_samples-th nearest neighbour NOT counting the point itself. scikit-learn >= 1.3 counts the
//   point; its min_samples = m equals ours = m - 1. match_reference_implementation reproduces
//   Campello et al.'s code as Python hdbscan does: min_samples - 1, min_cluster_size + 1, and
//   points leave a cluster only strictly after its birth.
// - Exact and dense: Prim's minimum spanning tree over all pairs, O(n^2 d) time and O(n d)
//   memory, limited to kHdbscanMaxPoints points (20k points of 16-d: 4.7 s of CPU, bench/hdbscan;
//   50k: about 30 s).
// - Ties in mutual reachability are broken as hdbscan 0.8.33's `generic` algorithm breaks them
//   (Prim from point 0, lowest index first, NumPy's argsort order of equal edge weights), so
//   labels agree with it exactly, not just up to equally valid alternatives.
// - Deterministic: the result does not depend on the number of threads.
#pragma once

#include <string>
#include <vector>

#include "nodes/lifting/condensed_tree.hpp"
#include "nodes/lifting/single_linkage.hpp"
#include "param/param_table.hpp"

namespace gslift {

constexpr int64_t kHdbscanMaxPoints = 50000;

enum class HdbscanMetric {
  Euclidean,
  // Rows are L2-normalised first, then compared with the Euclidean (chord) distance
  // sqrt(2 - 2 cos): it orders every pair as the cosine distance does, so the spanning tree and
  // cluster hierarchy are the cosine ones, while lambdas are in chord units (range 0..2).
  // Zero rows are rejected.
  Cosine,
};

struct HdbscanParams {
  // Smallest group of points that counts as a cluster (>= 2). LaGa/SAGA use 5..10 on features.
  int min_cluster_size = 5;
  // Neighbourhood size of the core distance; 0 = min_cluster_size (Python hdbscan's default).
  // Larger values smooth the density estimate and declare more points noise.
  int min_samples = 0;
  HdbscanMetric metric = HdbscanMetric::Euclidean;
  ClusterSelection selection = ClusterSelection::ExcessOfMass;
  // See FlatClusteringOptions (condensed_tree.hpp); 0 disables. LaGa 0.1, SAGA 0.01.
  double cluster_selection_epsilon = 0.0;
  bool allow_single_cluster = false;
  bool match_reference_implementation = false;
};

// "cosine"/"euclidean": the names of the metrics, for node params.
const EnumNames<HdbscanMetric>& hdbscan_metric_names();
// Name -> enum ("euclidean"/"cosine", "eom"/"leaf"). Throw std::invalid_argument naming the valid
// values.
HdbscanMetric parse_hdbscan_metric(const std::string& name);
ClusterSelection parse_cluster_selection(const std::string& name);

struct HdbscanResult {
  std::vector<int> labels;            // per point, -1 for noise (labels_)
  std::vector<double> probabilities;  // per point, in [0, 1], 0 for noise (probabilities_)
  int clusters = 0;
};

// Points as rows. Throws std::invalid_argument for invalid params, non-finite coordinates, zero
// rows under the cosine metric, or more than kHdbscanMaxPoints points. Fewer than 2 points: all
// noise.
// `cannot_link` (condensed_tree.hpp) constrains the excess-of-mass selection; empty = plain
// HDBSCAN.
HdbscanResult hdbscan(const PointMatrix& points, const HdbscanParams& params,
                      const CannotLink& cannot_link = {});

}  // namespace gslift
