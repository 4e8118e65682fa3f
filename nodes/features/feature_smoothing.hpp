// The public SAGA v2 code's local feature smoothing (get_smoothed_point_features;
// ../shared/reference/method-anchors.md §1.3): each Gaussian's feature is replaced by the mean of
// the L2-normalised features of its K nearest Gaussians (by centre, the Gaussian itself included,
// computed once). In training each step keeps a random half of the K neighbour slots, the same
// slots for every Gaussian (torch.randperm(K)[:K/2]); the saved features use all K.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gslift {

class FeatureSmoothing {
 public:
  // means: N x 3 centres. k >= 1 (clamped to N).
  FeatureSmoothing(const std::vector<float>& means, int k);

  int k() const { return k_; }
  // out (N x dim) = per Gaussian the mean of unit[neighbour in slot s] over `slots` (indices in
  // [0, k), nearest first).
  void smooth(const float* unit, int dim, const std::vector<int>& slots, float* out) const;
  // The adjoint: grad_unit (N x dim) += the gradient of smooth() given grad_out. Each Gaussian's
  // sum runs in a fixed order: deterministic at any thread count.
  void backward(const float* grad_out, int dim, const std::vector<int>& slots,
                float* grad_unit) const;

 private:
  int k_ = 1;
  size_t n_ = 0;
  std::vector<uint32_t> neighbours_;  // N x k, nearest first (the Gaussian itself in slot 0)
  // Reverse lists: Gaussian m is neighbour slot (e % k) of Gaussian e / k for every e in
  // reverse_[reverse_offsets_[m] .. reverse_offsets_[m + 1]).
  std::vector<uint32_t> reverse_offsets_, reverse_;
};

}  // namespace gslift
