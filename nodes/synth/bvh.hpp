// Bounding-volume hierarchy over the scene's primitives: surface-area-heuristic splits,
// flattened into a depth-first array so traversal is a tight loop with a small stack and
// visits the near child first. Primitives as large as the scene (floor, walls, ceiling) would
// make every node span the whole room, so they are kept out of the tree and tested directly.
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "nodes/synth/primitive.hpp"

namespace gslift::synth {

struct RayHit {
  int primitive = -1;  // index into the primitives, -1 = miss
  Hit hit;
};

class Bvh {
 public:
  // Keeps a reference to `primitives`; they must outlive the Bvh and not change.
  explicit Bvh(const std::vector<Primitive>& primitives);

  // Nearest hit with t in (t_min, t_max).
  RayHit closest(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_min,
                 float t_max) const;
  // Any hit with t in (t_min, t_max) on a primitive that casts shadows: shadow rays stop at the
  // first blocker.
  bool occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_min,
                float t_max) const;

 private:
  struct Node {
    Eigen::AlignedBox3f box;
    int first = 0;  // leaf: first index into order_; inner: index of the right child
    int count = 0;  // > 0 for leaves
    int axis = 0;   // inner: split axis (the near child depends on the ray's sign along it)
  };
  int build(int begin, int end);
  template <bool kAnyHit>
  RayHit traverse(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_min,
                  float t_max) const;

  const std::vector<Primitive>& primitives_;
  std::vector<Eigen::AlignedBox3f> boxes_;
  std::vector<int> order_;  // tree primitives, leaves index ranges of it
  std::vector<int> large_;  // primitives tested for every ray
  std::vector<Node> nodes_;
};

}  // namespace gslift::synth
