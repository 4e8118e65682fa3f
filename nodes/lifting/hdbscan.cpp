#include "nodes/lifting/hdbscan.hpp"

#include <algorithm>
#include <stdexcept>

namespace gslift {

const EnumNames<HdbscanMetric>& hdbscan_metric_names() {
  static const EnumNames<HdbscanMetric> names = {{HdbscanMetric::Cosine, "cosine"},
                                                 {HdbscanMetric::Euclidean, "euclidean"}};
  return names;
}

HdbscanMetric parse_hdbscan_metric(const std::string& name) {
  return parse_enum(name, hdbscan_metric_names(), "HDBSCAN metric");
}

ClusterSelection parse_cluster_selection(const std::string& name) {
  if (name == "eom") return ClusterSelection::ExcessOfMass;
  if (name == "leaf") return ClusterSelection::Leaf;
  throw std::invalid_argument("unknown cluster selection '" + name + "' (eom, leaf)");
}

HdbscanResult hdbscan(const PointMatrix& points, const HdbscanParams& params,
                      const CannotLink& cannot_link) {
  if (params.min_cluster_size < 2)
    throw std::invalid_argument("HDBSCAN: min_cluster_size must be at least 2");
  if (params.min_samples < 0) throw std::invalid_argument("HDBSCAN: min_samples must be >= 0");
  if (params.cluster_selection_epsilon < 0)
    throw std::invalid_argument("HDBSCAN: cluster_selection_epsilon must be >= 0");
  const int64_t n = points.rows();
  if (n > kHdbscanMaxPoints)
    throw std::invalid_argument("HDBSCAN: " + std::to_string(n) + " points exceed the limit of " +
                                std::to_string(kHdbscanMaxPoints) +
                                " of the exact O(n^2) algorithm; subsample the points");
  if (!points.allFinite()) throw std::invalid_argument("HDBSCAN: points contain NaN or infinity");

  HdbscanResult result;
  result.labels.assign(n, -1);
  result.probabilities.assign(n, 0.0);
  if (n < 2) return result;

  PointMatrix normalised;
  if (params.metric == HdbscanMetric::Cosine) {
    normalised = points;
    for (int64_t i = 0; i < n; ++i) {
      const double norm = normalised.row(i).norm();
      if (norm == 0.0)
        throw std::invalid_argument("HDBSCAN: point " + std::to_string(i) +
                                    " is zero, it has no cosine distance");
      normalised.row(i) /= norm;
    }
  }
  const PointMatrix& x = params.metric == HdbscanMetric::Cosine ? normalised : points;

  int min_samples = params.min_samples > 0 ? params.min_samples : params.min_cluster_size;
  int64_t min_cluster_size = params.min_cluster_size;
  if (params.match_reference_implementation) {
    min_samples -= 1;
    min_cluster_size += 1;
  }
  min_samples = static_cast<int>(std::min<int64_t>(n - 1, min_samples));
  min_samples = std::max(min_samples, 1);

  const std::vector<double> core = core_distances(x, min_samples);
  const std::vector<LinkageMerge> hierarchy = single_linkage(mutual_reachability_mst(x, core));
  const std::vector<CondensedEdge> tree = condense_tree(hierarchy, min_cluster_size);

  FlatClusteringOptions options;
  options.selection = params.selection;
  options.cluster_selection_epsilon = params.cluster_selection_epsilon;
  options.allow_single_cluster = params.allow_single_cluster;
  options.match_reference_implementation = params.match_reference_implementation;
  options.cannot_link = cannot_link;
  FlatClustering flat = extract_clusters(tree, n, options);
  result.labels = std::move(flat.labels);
  result.probabilities = std::move(flat.probabilities);
  result.clusters = flat.clusters;
  return result;
}

}  // namespace gslift
