#include "nodes/synth/bvh.hpp"

#include <algorithm>
#include <limits>

namespace gslift::synth {

namespace {

constexpr int kLeafSize = 2;
// A primitive whose bounds exceed this fraction of the scene's diagonal stays out of the tree.
constexpr float kLargeFraction = 0.5f;

// Slab test of a ray against a box; inv_dir = 1 / dir component-wise (inf where dir is 0, which
// gives +-inf slab distances and the right answer). Branch-free: it is the hottest loop.
bool ray_hits_box(const Eigen::AlignedBox3f& box, const Eigen::Vector3f& origin,
                  const Eigen::Vector3f& inv_dir, float t_min, float t_max) {
  const Eigen::Array3f t0 = (box.min() - origin).array() * inv_dir.array();
  const Eigen::Array3f t1 = (box.max() - origin).array() * inv_dir.array();
  return std::max(t_min, t0.min(t1).maxCoeff()) <= std::min(t_max, t0.max(t1).minCoeff());
}

}  // namespace

Bvh::Bvh(const std::vector<Primitive>& primitives) : primitives_(primitives) {
  boxes_.reserve(primitives.size());
  for (const auto& p : primitives) boxes_.push_back(bounds(p));
  Eigen::AlignedBox3f scene;
  for (const auto& b : boxes_) scene.extend(b);
  for (int i = 0; i < static_cast<int>(primitives.size()); ++i) {
    const bool large = boxes_[i].diagonal().norm() > kLargeFraction * scene.diagonal().norm();
    (large ? large_ : order_).push_back(i);
  }
  if (!order_.empty()) build(0, static_cast<int>(order_.size()));
}

int Bvh::build(int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3f box;
  for (int i = begin; i < end; ++i) box.extend(boxes_[order_[i]]);
  nodes_[index].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  // Surface-area heuristic: on each axis, sort by centroid and take the split that minimises
  // area(left) * n_left + area(right) * n_right, the expected cost of a random ray. Scenes have
  // about a hundred primitives, so the exhaustive sweep is cheap. Ties are broken by index so the
  // tree does not depend on the sort implementation.
  auto area = [](const Eigen::AlignedBox3f& b) {
    const Eigen::Vector3f d = b.sizes();
    return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
  };
  const int n = end - begin;
  float best_cost = std::numeric_limits<float>::infinity();
  int best_axis = 0, best_split = n / 2;
  std::vector<int> sorted(order_.begin() + begin, order_.begin() + end);
  std::vector<float> left_area(n);
  for (int axis = 0; axis < 3; ++axis) {
    std::sort(sorted.begin(), sorted.end(), [&](int a, int b) {
      const float ca = boxes_[a].center()[axis], cb = boxes_[b].center()[axis];
      return ca < cb || (ca == cb && a < b);
    });
    Eigen::AlignedBox3f acc;
    for (int k = 0; k < n; ++k) left_area[k] = area(acc.extend(boxes_[sorted[k]]));
    acc.setEmpty();
    for (int k = n - 1; k >= 1; --k) {
      // Left = sorted[0..k), right = sorted[k..n).
      const float cost = left_area[k - 1] * k + area(acc.extend(boxes_[sorted[k]])) * (n - k);
      if (cost < best_cost) best_cost = cost, best_axis = axis, best_split = k;
    }
  }
  std::sort(order_.begin() + begin, order_.begin() + end, [&](int a, int b) {
    const float ca = boxes_[a].center()[best_axis], cb = boxes_[b].center()[best_axis];
    return ca < cb || (ca == cb && a < b);
  });
  nodes_[index].axis = best_axis;
  build(begin, begin + best_split);
  const int right = build(begin + best_split, end);
  nodes_[index].first = right;
  return index;
}

template <bool kAnyHit>
RayHit Bvh::traverse(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_min,
                     float t_max) const {
  RayHit result;
  for (int i : large_) {
    if (kAnyHit && !primitives_[i].casts_shadow) continue;
    Hit hit;
    if (!intersect(primitives_[i], origin, dir, t_min, t_max, hit)) continue;
    result.primitive = i;
    result.hit = hit;
    if (kAnyHit) return result;
    t_max = hit.t;
  }
  if (nodes_.empty()) return result;
  const Eigen::Vector3f inv_dir = dir.cwiseInverse();
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!ray_hits_box(node.box, origin, inv_dir, t_min, t_max)) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        if (kAnyHit && !primitives_[order_[i]].casts_shadow) continue;
        Hit hit;
        if (!intersect(primitives_[order_[i]], origin, dir, t_min, t_max, hit)) continue;
        result.primitive = order_[i];
        result.hit = hit;
        if (kAnyHit) return result;
        t_max = hit.t;
      }
      continue;
    }
    // Push the far child first so the near one is visited first and shrinks t_max early.
    const int left = static_cast<int>(&node - nodes_.data()) + 1, right = node.first;
    const bool right_is_near = dir[node.axis] < 0;
    stack[top++] = right_is_near ? left : right;
    stack[top++] = right_is_near ? right : left;
  }
  return result;
}

RayHit Bvh::closest(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_min,
                    float t_max) const {
  return traverse<false>(origin, dir, t_min, t_max);
}

bool Bvh::occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_min,
                   float t_max) const {
  return traverse<true>(origin, dir, t_min, t_max).primitive >= 0;
}

}  // namespace gslift::synth
