// SAGA's correspondence loss (paper 001 §4.2): pixels that SAM puts in the same masks should have
// similar rendered affinity features, pixels it separates dissimilar ones. For two pixels,
//   K(p1, p2) = |M(p1) ∩ M(p2)| / |M(p1) ∪ M(p2)|,   0 replaced by -1,
// where M(p) is the set of (multi-granularity) masks that contain p, and
//   L_corr = - mean over pairs p1 != p2 of K(p1, p2) cos(F(p1), F(p2)).
// Pixels covered by no mask have no K and are never sampled (as in the public code).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "nodes/scene/masks.hpp"

namespace gslift {

// Mask membership of pixels as bitsets: `words` 64-bit words per pixel, bit m of pixel p set when
// mask m contains p.
struct MaskMembership {
  int words = 0;
  std::vector<uint64_t> bits;  // pixels x words
  const uint64_t* pixel(size_t p) const { return bits.data() + p * words; }
};

// One view's masks as membership bitsets, and the pixels covered by some mask (row-major).
struct MaskedPixels {
  MaskMembership membership;
  std::vector<uint32_t> covered;
};
MaskedPixels masked_pixels(const ViewMasks& masks, size_t pixels);

// K(p, q) of two membership bitsets: IoU of the mask sets, -1 when they share no mask (or when
// both are empty).
float mask_set_affinity(const uint64_t* a, const uint64_t* b, int words);

// K for every pair of the sampled pixels (P x P, symmetric; the diagonal is 0: a pixel is never
// paired with itself).
Eigen::MatrixXf correspondence_kernel(const MaskMembership& membership,
                                      const std::vector<uint32_t>& pixels);

// L_corr of the P x D rendered features (one row per sampled pixel) under K (P x P, diagonal
// ignored), averaged over the P (P - 1) / 2 unordered pairs. When grad is given it receives
// dL/dF (P x D): with u_i = F_i / |F_i| and g_i = sum_{j != i} K_ij u_j,
//   dL/dF_i = -(g_i - <g_i, u_i> u_i) / (|F_i| * pairs).
// Rows with |F_i| below 1e-12 count as cos 0 and get no gradient. Needs P >= 2.
double correspondence_loss(const Eigen::MatrixXf& features, const Eigen::MatrixXf& kernel,
                           Eigen::MatrixXf* grad);

}  // namespace gslift
