#include "nodes/inference/filter_3d.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>

#include <open3d/geometry/KDTreeFlann.h>
#include <tbb/parallel_for.h>

namespace gslift {
namespace {

Eigen::MatrixXd centres(const std::vector<float>& means, const std::vector<size_t>& members) {
  Eigen::MatrixXd m(3, members.size());
  for (size_t j = 0; j < members.size(); ++j)
    for (int c = 0; c < 3; ++c) m(c, j) = means[3 * members[j] + c];
  return m;
}

// Mean distance of every point to its k nearest other points (the point itself left out, also
// when another point sits at the same place).
std::vector<double> mean_knn_distance(const Eigen::MatrixXd& pts, int k) {
  const open3d::geometry::KDTreeFlann tree(pts);
  std::vector<double> mean(pts.cols());
  tbb::parallel_for(Eigen::Index(0), pts.cols(), [&](Eigen::Index i) {
    std::vector<int> idx;
    std::vector<double> d2;
    tree.SearchKNN(Eigen::Vector3d(pts.col(i)), k + 1, idx, d2);
    double sum = 0;
    int used = 0;
    bool self_skipped = false;
    for (size_t j = 0; j < idx.size() && used < k; ++j) {
      if (!self_skipped && idx[j] == i) {
        self_skipped = true;
        continue;
      }
      sum += std::sqrt(d2[j]);
      ++used;
    }
    mean[i] = used ? sum / used : 0.0;
  });
  return mean;
}

// The largest distance from a point to its nearest other point.
double largest_nn_distance(const Eigen::MatrixXd& pts) {
  if (pts.cols() < 2) return 0;
  const std::vector<double> nn = mean_knn_distance(pts, 1);
  return *std::max_element(nn.begin(), nn.end());
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Component index per point: points at most r apart are linked (union-find over radius searches;
// the search itself is strict, so r is widened by a relative 1e-9 to keep the pair that defines
// r linked).
std::vector<int> components_within(const Eigen::MatrixXd& pts, double r) {
  r *= 1 + 1e-9;
  const int n = static_cast<int>(pts.cols());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const open3d::geometry::KDTreeFlann tree(pts);
  std::vector<int> idx;
  std::vector<double> d2;
  for (int i = 0; i < n; ++i) {
    tree.SearchRadius(Eigen::Vector3d(pts.col(i)), r, idx, d2);
    for (const int j : idx) {
      const int a = find_root(parent, i), b = find_root(parent, j);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the smaller index is the root
    }
  }
  std::vector<int> label(n);
  for (int i = 0; i < n; ++i) label[i] = find_root(parent, i);
  return label;
}

Eigen::VectorXf unit_feature(const std::vector<float>& features, int dim, size_t g) {
  Eigen::VectorXf f = Eigen::Map<const Eigen::VectorXf>(features.data() + g * dim, dim);
  const float norm = f.norm();
  return norm > 0 ? Eigen::VectorXf(f / norm) : f;
}

// Per instance, the normalised mean of its kept Gaussians' normalised features.
std::map<int32_t, Eigen::VectorXf> feature_prototypes(const std::vector<float>& features, int dim,
                                                      const std::vector<size_t>& kept_all,
                                                      const std::vector<int32_t>& kept_instance) {
  std::map<int32_t, Eigen::VectorXf> sum;
  for (size_t j = 0; j < kept_all.size(); ++j) {
    auto [it, fresh] = sum.try_emplace(kept_instance[j], Eigen::VectorXf::Zero(dim));
    it->second += unit_feature(features, dim, kept_all[j]);
  }
  for (auto& [id, s] : sum)
    if (s.norm() > 0) s.normalize();
  return sum;
}

}  // namespace

Filter3dResult filter_instances_3d(const std::vector<float>& means,
                                   const std::vector<int32_t>& instance_ids,
                                   const Filter3dOptions& o, const std::vector<float>& features,
                                   int feature_dim, const GrowthExclusion& excluded) {
  filter_3d_param_table().validate(o, "inference.filter_3d");
  if (means.size() != 3 * instance_ids.size())
    throw std::invalid_argument("filter_3d: " + std::to_string(means.size() / 3) +
                                " Gaussians but " + std::to_string(instance_ids.size()) +
                                " instance ids");
  const bool feature_gate = o.grow && o.growth_min_similarity > -1;
  if (feature_gate &&
      (feature_dim <= 0 || features.size() != size_t(feature_dim) * instance_ids.size()))
    throw std::invalid_argument(
        "filter_3d: growth_min_similarity needs the Gaussians' features (the model has " +
        std::to_string(feature_dim) + " feature channels)");
  for (const auto& [id, flags] : excluded)
    if (flags.size() != instance_ids.size())
      throw std::invalid_argument("filter_3d: instance " + std::to_string(id) +
                                  "'s exclusion has " + std::to_string(flags.size()) +
                                  " flags for " + std::to_string(instance_ids.size()) +
                                  " Gaussians");
  Filter3dResult result;
  result.instance_ids = instance_ids;
  std::map<int32_t, std::vector<size_t>> members;  // ordered: results do not depend on hashing
  for (size_t g = 0; g < instance_ids.size(); ++g)
    if (instance_ids[g] >= 0) members[instance_ids[g]].push_back(g);

  // The kept Gaussians of every instance, and each instance's growth radius.
  std::vector<size_t> kept_all;
  std::vector<int32_t> kept_instance;
  std::map<int32_t, double> radius;
  std::map<int32_t, std::pair<Eigen::Vector3d, Eigen::Vector3d>> box;  // growth_box_margin
  for (auto& [id, list] : members) {
    if (static_cast<int>(list.size()) < o.min_instance_size) continue;
    std::vector<size_t> kept = list;
    if (o.statistical) {
      const int k = std::max(1, static_cast<int>(std::lround(std::sqrt(double(list.size())))));
      const std::vector<double> d = mean_knn_distance(centres(means, list), k);
      double mu = 0, var = 0;
      for (const double x : d) mu += x;
      mu /= d.size();
      for (const double x : d) var += (x - mu) * (x - mu);
      const double limit = mu + o.std_ratio * std::sqrt(var / d.size());
      kept.clear();
      for (size_t j = 0; j < list.size(); ++j) {
        if (d[j] <= limit) {
          kept.push_back(list[j]);
        } else {
          result.instance_ids[list[j]] = -1;
          ++result.outliers;
        }
      }
    }
    const Eigen::MatrixXd pts = centres(means, kept);
    const double r = largest_nn_distance(pts);
    if (o.components && kept.size() > 1) {
      const std::vector<int> label = components_within(pts, r);
      std::map<int, size_t> size;
      for (const int l : label) ++size[l];
      size_t largest = 0;
      for (const auto& [l, s] : size) largest = std::max(largest, s);
      std::vector<size_t> in_kept_components;
      for (size_t j = 0; j < kept.size(); ++j) {
        const size_t s = size[label[j]];
        if (s == largest || s >= o.min_component_fraction * kept.size()) {
          in_kept_components.push_back(kept[j]);
        } else {
          result.instance_ids[kept[j]] = -1;
          ++result.component_dropped;
        }
      }
      kept = std::move(in_kept_components);
    }
    radius[id] = r;
    if (o.growth_box_margin >= 0 && !kept.empty()) {
      const Eigen::MatrixXd k = centres(means, kept);
      const Eigen::Vector3d lo = k.rowwise().minCoeff(), hi = k.rowwise().maxCoeff();
      const Eigen::Vector3d pad = o.growth_box_margin * (hi - lo);
      box[id] = {lo - pad, hi + pad};
    }
    result.growth.push_back({id, static_cast<int64_t>(list.size()),
                             static_cast<int64_t>(kept.size()), static_cast<int64_t>(kept.size()),
                             static_cast<int64_t>(kept.size()), false});
    for (const size_t g : kept) {
      kept_all.push_back(g);
      kept_instance.push_back(id);
    }
  }

  // Growth reaches the Gaussians unassigned on input and those the steps above took from the
  // same instance (SAGA's ball query runs over the whole scene, so it restores the edge that the
  // one-sided mu + sigma cut clips off even a clean surface), never another instance's.
  if (o.grow && !kept_all.empty()) {
    std::vector<char> is_kept(instance_ids.size(), 0);
    for (const size_t g : kept_all) is_kept[g] = 1;
    // Open3D 0.16's KDTreeFlann searches the matrix it was built from, not its own copy: the
    // matrix must outlive the tree. (It was a temporary: the searches read freed memory, whose
    // reuse depended on the other threads' allocations, so growth changed with the thread count.)
    const Eigen::MatrixXd kept_centres = centres(means, kept_all);
    const open3d::geometry::KDTreeFlann tree(kept_centres);
    const std::map<int32_t, Eigen::VectorXf> prototype =
        feature_gate ? feature_prototypes(features, feature_dim, kept_all, kept_instance)
                     : std::map<int32_t, Eigen::VectorXf>{};
    std::vector<int32_t> joined(instance_ids.size(), -1);
    std::vector<char> was_excluded(instance_ids.size(), 0);
    tbb::parallel_for(size_t(0), instance_ids.size(), [&](size_t g) {
      if (is_kept[g]) return;
      std::vector<int> idx;
      std::vector<double> d2;
      const Eigen::Vector3d p(means[3 * g], means[3 * g + 1], means[3 * g + 2]);
      const Eigen::VectorXf f =
          feature_gate ? unit_feature(features, feature_dim, g) : Eigen::VectorXf();
      // The nearest kept Gaussian (among the 8 nearest) whose instance may take this one and
      // whose radius reaches it.
      tree.SearchKNN(p, 8, idx, d2);
      for (size_t j = 0; j < idx.size(); ++j) {
        const int32_t id = kept_instance[idx[j]];
        if (instance_ids[g] >= 0 && instance_ids[g] != id) continue;
        const auto b = box.find(id);
        if (b != box.end() && ((p.array() < b->second.first.array()).any() ||
                               (p.array() > b->second.second.array()).any()))
          continue;
        if (feature_gate && f.dot(prototype.at(id)) < o.growth_min_similarity) continue;
        if (std::sqrt(d2[j]) > radius.at(id)) continue;
        const auto ex = excluded.find(id);
        if (ex != excluded.end() && ex->second[g]) {
          was_excluded[g] = 1;
          continue;
        }
        joined[g] = id;
        break;
      }
    });
    std::map<int32_t, int64_t> joins;
    for (size_t g = 0; g < joined.size(); ++g) {
      if (joined[g] >= 0) ++joins[joined[g]];
      result.excluded += joined[g] < 0 && was_excluded[g];
    }
    const double scene = static_cast<double>(instance_ids.size());
    std::map<int32_t, bool> refuse;
    for (Filter3dResult::Growth& g : result.growth) {
      g.would_be = g.kept + joins[g.id];
      refuse[g.id] = g.refused =
          (o.max_growth_ratio > 0 && g.would_be > o.max_growth_ratio * g.kept) ||
          g.would_be > o.max_scene_fraction * scene;
      if (!g.refused) g.after = g.would_be;
      result.refused += g.refused;
    }
    for (size_t g = 0; g < joined.size(); ++g)
      if (joined[g] >= 0 && !refuse[joined[g]]) {
        result.instance_ids[g] = joined[g];
        ++(instance_ids[g] < 0 ? result.grown : result.restored);
      }
  }
  return result;
}

const ParamTable<Filter3dOptions>& filter_3d_param_table() {
  using O = Filter3dOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("statistical", &O::statistical,
               "drop Gaussians whose mean distance to their sqrt(n) nearest instance neighbours "
               "exceeds mu + std_ratio sigma")
          .add("std_ratio", &O::std_ratio, "sigmas above the mean distance (SAGA: 1)", 0)
          .add("components", &O::components,
               "keep only the connected components (link: the largest nearest-neighbour distance) "
               "that hold the instance's mass")
          .add("min_component_fraction", &O::min_component_fraction,
               "a component besides the largest is kept with at least this fraction of the "
               "instance's Gaussians",
               0, 1)
          .add("grow", &O::grow,
               "unassigned Gaussians within the growth radius of an instance join it (ball query)")
          .add("min_instance_size", &O::min_instance_size,
               "instances with fewer Gaussians are left as they are", 2)
          .add("growth_box_margin", &O::growth_box_margin,
               "growth stays inside the kept Gaussians' box widened by this fraction of its "
               "extent per side (SAGA: 0.05); negative = no box")
          .add("max_growth_ratio", &O::max_growth_ratio,
               "growth is refused (the un-grown instance kept) when it would leave an instance "
               "more than this many times its size before growth; 0 = no bound",
               0)
          .add("max_scene_fraction", &O::max_scene_fraction,
               "growth is refused when it would leave an instance more than this fraction of "
               "the scene's Gaussians; 1 = no bound",
               0, 1)
          .add("growth_min_similarity", &O::growth_min_similarity,
               "a Gaussian joins by growth only when its feature's cosine similarity to the "
               "instance's mean feature reaches this (growth stops at feature edges); -1 = no "
               "check",
               -1, 1);
  return table;
}

}  // namespace gslift
