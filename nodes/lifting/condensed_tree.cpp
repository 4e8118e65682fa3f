#include "nodes/lifting/condensed_tree.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace gslift {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Breadth-first order of the subtree of `root`, level by level, left before right
// (bfs_from_hierarchy).
std::vector<int64_t> hierarchy_bfs(const std::vector<LinkageMerge>& hierarchy, int64_t root,
                                   int64_t num_points) {
  std::vector<int64_t> result, level{root}, next;
  while (!level.empty()) {
    result.insert(result.end(), level.begin(), level.end());
    next.clear();
    for (const int64_t x : level) {
      if (x < num_points) continue;
      next.push_back(hierarchy[x - num_points].left);
      next.push_back(hierarchy[x - num_points].right);
    }
    level.swap(next);
  }
  return result;
}

// The clusters of a condensed tree (ids root .. root + count - 1) and how they nest.
struct ClusterTree {
  int64_t root = 0;
  std::vector<int64_t> parent;                 // -1 for the root
  std::vector<std::vector<int64_t>> children;  // in tree row order
  std::vector<double> birth;                   // lambda at which the cluster split off; 0 root
  std::vector<double> death;                   // largest lambda of its own rows (max_lambdas)
  std::vector<double> stability;               // compute_stability

  int64_t count() const { return static_cast<int64_t>(parent.size()); }
  int64_t index(int64_t cluster) const { return cluster - root; }

  // Descendants of `cluster` (excluding it), breadth first.
  std::vector<int64_t> descendants(int64_t cluster) const {
    std::vector<int64_t> out;
    std::vector<int64_t> todo = children[index(cluster)];
    for (size_t i = 0; i < todo.size(); ++i) {
      out.push_back(todo[i]);
      for (const int64_t c : children[index(todo[i])]) todo.push_back(c);
    }
    return out;
  }
};

ClusterTree build_cluster_tree(const std::vector<CondensedEdge>& tree, int64_t num_points) {
  ClusterTree ct;
  ct.root = num_points;
  int64_t max_cluster = num_points;
  for (const auto& e : tree) max_cluster = std::max(max_cluster, e.parent);
  const int64_t count = max_cluster - num_points + 1;
  ct.parent.assign(count, -1);
  ct.children.assign(count, {});
  ct.birth.assign(count, 0.0);
  ct.death.assign(count, 0.0);
  ct.stability.assign(count, 0.0);
  for (const auto& e : tree) {
    if (e.child >= num_points) {
      ct.parent[ct.index(e.child)] = e.parent;
      ct.children[ct.index(e.parent)].push_back(e.child);
      ct.birth[ct.index(e.child)] = e.lambda;
    }
    double& death = ct.death[ct.index(e.parent)];
    death = std::max(death, e.lambda);
  }
  // Stability (excess of mass) of a cluster: sum over its rows of (lambda - birth) * size, in row
  // order as compute_stability sums it.
  for (const auto& e : tree)
    ct.stability[ct.index(e.parent)] +=
        (e.lambda - ct.birth[ct.index(e.parent)]) * static_cast<double>(e.child_size);
  return ct;
}

// Leaves of the cluster tree below the root, depth first (get_cluster_tree_leaves).
void collect_leaves(const ClusterTree& ct, int64_t cluster, std::vector<int64_t>& leaves) {
  const auto& kids = ct.children[ct.index(cluster)];
  if (kids.empty()) {
    leaves.push_back(cluster);
    return;
  }
  for (const int64_t c : kids) collect_leaves(ct, c, leaves);
}

// The ancestor of `leaf` that replaces it under cluster_selection_epsilon (traverse_upwards).
int64_t epsilon_ancestor(const ClusterTree& ct, double epsilon, int64_t leaf,
                         bool allow_single_cluster) {
  const int64_t parent = ct.parent[ct.index(leaf)];
  if (parent == ct.root) return allow_single_cluster ? parent : leaf;
  if (1.0 / ct.birth[ct.index(parent)] > epsilon) return parent;
  return epsilon_ancestor(ct, epsilon, parent, allow_single_cluster);
}

// Replaces each candidate born below epsilon by its epsilon ancestor (epsilon_search); candidates
// are visited in ascending id order.
std::set<int64_t> epsilon_search(const ClusterTree& ct, const std::set<int64_t>& candidates,
                                 double epsilon, bool allow_single_cluster) {
  std::set<int64_t> selected, processed;
  for (const int64_t leaf : candidates) {
    if (1.0 / ct.birth[ct.index(leaf)] < epsilon) {
      if (processed.count(leaf)) continue;
      const int64_t chosen = epsilon_ancestor(ct, epsilon, leaf, allow_single_cluster);
      selected.insert(chosen);
      for (const int64_t d : ct.descendants(chosen)) processed.insert(d);
    } else {
      selected.insert(leaf);
    }
  }
  return selected;
}

// Per cluster of the condensed tree, whether it holds both groups of a cannot-link pair (more
// than half of each group's points fell out of it or of its descendants).
std::vector<char> cannot_link_violations(const ClusterTree& ct,
                                         const std::vector<CondensedEdge>& tree, int64_t num_points,
                                         const CannotLink& cl) {
  std::vector<char> violates(ct.count(), 0);
  if (cl.empty()) return violates;
  if (static_cast<int64_t>(cl.point_groups.size()) != num_points)
    throw std::invalid_argument("HDBSCAN: cannot-link groups for " +
                                std::to_string(cl.point_groups.size()) + " points, expected " +
                                std::to_string(num_points));
  int groups = 0;
  for (const int g : cl.point_groups) groups = std::max(groups, g + 1);
  for (const auto& [a, b] : cl.pairs)
    if (a < 0 || b < 0 || a >= groups || b >= groups)
      throw std::invalid_argument("HDBSCAN: a cannot-link pair names a group without points");
  std::vector<int64_t> group_size(groups, 0);
  // held[c * groups + g]: points of group g in cluster c's subtree.
  std::vector<int64_t> held(static_cast<size_t>(ct.count()) * groups, 0);
  for (const auto& e : tree) {
    if (e.child >= num_points) continue;
    const int g = cl.point_groups[e.child];
    if (g < 0) continue;
    ++group_size[g];
    for (int64_t c = e.parent; c >= 0; c = ct.parent[ct.index(c)])
      ++held[static_cast<size_t>(ct.index(c)) * groups + g];
  }
  for (int64_t c = 0; c < ct.count(); ++c) {
    const int64_t* h = held.data() + static_cast<size_t>(c) * groups;
    for (const auto& [a, b] : cl.pairs)
      if (2 * h[a] > group_size[a] && 2 * h[b] > group_size[b]) {
        violates[c] = 1;
        break;
      }
  }
  return violates;
}

std::set<int64_t> select_excess_of_mass(ClusterTree& ct, const FlatClusteringOptions& o,
                                        const std::vector<char>& violates) {
  // Reverse id order is a bottom-up order: children always get larger ids than their parent.
  std::map<int64_t, bool> is_cluster;
  for (int64_t c = ct.root + ct.count() - 1; c >= ct.root; --c) {
    if (c == ct.root && !o.allow_single_cluster) break;
    is_cluster[c] = true;
  }
  for (auto it = is_cluster.rbegin(); it != is_cluster.rend(); ++it) {
    const int64_t node = it->first;
    double children_sum = 0.0;
    for (const int64_t c : ct.children[ct.index(node)]) children_sum += ct.stability[ct.index(c)];
    // hdbscan 0.8.33 holds this sum in a C float (`cdef float subtree_stability`); rounding it the
    // same way keeps near-ties between a cluster and its children decided as in the reference.
    const float subtree = static_cast<float>(children_sum);
    // A cluster that joins two cannot-linked groups gives way to its children (if it has any).
    const bool must_split = violates[ct.index(node)] && !ct.children[ct.index(node)].empty();
    if (must_split || subtree > ct.stability[ct.index(node)]) {
      it->second = false;
      ct.stability[ct.index(node)] = subtree;
    } else {
      for (const int64_t d : ct.descendants(node)) is_cluster[d] = false;
    }
  }
  std::set<int64_t> selected;
  for (const auto& [c, yes] : is_cluster)
    if (yes) selected.insert(c);
  if (o.cluster_selection_epsilon != 0.0 && ct.count() > 1) {
    if (selected.size() == 1 && *selected.begin() == ct.root) {
      if (!o.allow_single_cluster) selected.clear();
    } else {
      selected = epsilon_search(ct, selected, o.cluster_selection_epsilon, o.allow_single_cluster);
    }
  }
  return selected;
}

std::set<int64_t> select_leaves(const ClusterTree& ct, const FlatClusteringOptions& o) {
  if (ct.count() == 1) return {};  // no split at all: no leaf below the root
  std::vector<int64_t> leaves;
  collect_leaves(ct, ct.root, leaves);
  const std::set<int64_t> leaf_set(leaves.begin(), leaves.end());
  if (o.cluster_selection_epsilon == 0.0) return leaf_set;
  std::set<int64_t> selected =
      epsilon_search(ct, leaf_set, o.cluster_selection_epsilon, o.allow_single_cluster);
  if (!o.allow_single_cluster) selected.erase(ct.root);
  return selected;
}

}  // namespace

std::vector<CondensedEdge> condense_tree(const std::vector<LinkageMerge>& hierarchy,
                                         int64_t min_cluster_size) {
  std::vector<CondensedEdge> result;
  if (hierarchy.empty()) return result;
  const int64_t root = 2 * static_cast<int64_t>(hierarchy.size());
  const int64_t num_points = root / 2 + 1;
  int64_t next_label = num_points + 1;

  const std::vector<int64_t> node_list = hierarchy_bfs(hierarchy, root, num_points);
  std::vector<int64_t> relabel(root + 1, 0);
  relabel[root] = num_points;
  std::vector<char> ignore(node_list.size(), 0);

  auto size_of = [&](int64_t node) {
    return node >= num_points ? hierarchy[node - num_points].size : int64_t{1};
  };
  auto fall_out = [&](int64_t parent_label, int64_t subtree, double lambda) {
    for (const int64_t sub : hierarchy_bfs(hierarchy, subtree, num_points)) {
      if (sub < num_points) result.push_back({parent_label, sub, lambda, 1});
      ignore[sub] = 1;
    }
  };

  for (const int64_t node : node_list) {
    if (ignore[node] || node < num_points) continue;
    const LinkageMerge& m = hierarchy[node - num_points];
    const double lambda = m.distance > 0.0 ? 1.0 / m.distance : kInf;
    const int64_t left_count = size_of(m.left);
    const int64_t right_count = size_of(m.right);
    const bool left_big = left_count >= min_cluster_size;
    const bool right_big = right_count >= min_cluster_size;
    if (left_big && right_big) {
      relabel[m.left] = next_label++;
      result.push_back({relabel[node], relabel[m.left], lambda, left_count});
      relabel[m.right] = next_label++;
      result.push_back({relabel[node], relabel[m.right], lambda, right_count});
    } else if (!left_big && !right_big) {
      fall_out(relabel[node], m.left, lambda);
      fall_out(relabel[node], m.right, lambda);
    } else if (!left_big) {
      relabel[m.right] = relabel[node];
      fall_out(relabel[node], m.left, lambda);
    } else {
      relabel[m.left] = relabel[node];
      fall_out(relabel[node], m.right, lambda);
    }
  }
  return result;
}

FlatClustering extract_clusters(const std::vector<CondensedEdge>& tree, int64_t num_points,
                                const FlatClusteringOptions& options) {
  FlatClustering out;
  out.labels.assign(num_points, -1);
  out.probabilities.assign(num_points, 0.0);
  if (tree.empty()) return out;

  ClusterTree ct = build_cluster_tree(tree, num_points);
  const std::set<int64_t> selected =
      options.selection == ClusterSelection::ExcessOfMass
          ? select_excess_of_mass(ct, options,
                                  cannot_link_violations(ct, tree, num_points, options.cannot_link))
          : select_leaves(ct, options);
  std::map<int64_t, int> label_of;
  for (const int64_t c : selected) label_of.emplace(c, static_cast<int>(label_of.size()));
  out.clusters = static_cast<int>(label_of.size());

  // A point belongs to the nearest selected cluster above it (do_labelling's union-find), and
  // its membership probability is its lambda relative to that cluster's death (get_probabilities).
  for (const auto& e : tree) {
    if (e.child >= num_points) continue;
    int64_t cluster = e.parent;
    while (cluster != ct.root && !selected.count(cluster)) cluster = ct.parent[ct.index(cluster)];
    int label = -1;
    if (cluster == ct.root) {
      if (selected.size() == 1 && options.allow_single_cluster && selected.count(ct.root)) {
        const double threshold = options.cluster_selection_epsilon != 0.0
                                     ? 1.0 / options.cluster_selection_epsilon
                                     : ct.death[0];
        if (e.lambda >= threshold) label = label_of.at(ct.root);
      }
    } else if (!options.match_reference_implementation || e.lambda > ct.birth[ct.index(cluster)]) {
      label = label_of.at(cluster);
    }
    out.labels[e.child] = label;
    if (label < 0) continue;
    const double max_lambda = ct.death[ct.index(cluster)];
    out.probabilities[e.child] = (max_lambda == 0.0 || !std::isfinite(e.lambda))
                                     ? 1.0
                                     : std::min(e.lambda, max_lambda) / max_lambda;
  }
  return out;
}

}  // namespace gslift
