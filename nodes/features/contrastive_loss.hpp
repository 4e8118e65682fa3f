// LangOR Eq. 3, the mask-aware contrastive loss of one mask, on sampled rendered features.
//
// Paper: L_M = sum_{p in M} max(0, 1 - cos(f_m, F(p))) + lambda sum_{p not in M} max(0, cos(f_m,
// F(p))) with the centroid f_m = mean of F(p) over p in M. [decision] means instead
// of sums and pixels sampled per iteration: with n_in pixels sampled inside M and n_out outside,
//   f_m = (1/n_in) sum_{p in in} F(p),
//   L_M = (1/n_in) sum_{p in in} (1 - cos(f_m, F(p))) + lambda (1/n_out) sum_{p in out} max(0,
//   cos(f_m, F(p))).
// Sums would weight a mask by its area (a wall mask would drown a scalpel); means give every mask
// the same say, and the sampled centroid is an unbiased estimate of the mask's centroid.
// (1 - cos >= 0 always, so the inside hinge is the identity.)
//
// cos(a, b) = a.b / (|a|_e |b|_e) with the smoothed norm |a|_e = sqrt(a.a + kCosineEps^2): pixels
// that no Gaussian covers render F = 0, and the plain cosine has no gradient there.
#pragma once

namespace gslift {

inline constexpr double kCosineEps = 1e-6;

// Loss L_M of one mask and its gradient with respect to every sampled feature. inside: n_in x dim
// row-major rendered features of the pixels sampled in the mask (n_in >= 1); outside: n_out x dim
// (n_out may be 0: the mask covers the whole view, the repulsion term is left out). The
// gradients (same shapes) are OVERWRITTEN; the centroid's dependence on the inside features is
// included.
double mask_contrastive_loss(const float* inside, int n_in, const float* outside, int n_out,
                             int dim, double lambda, float* grad_inside, float* grad_outside);

}  // namespace gslift
