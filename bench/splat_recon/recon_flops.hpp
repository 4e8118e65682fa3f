// Floating-point work of one reconstruction step, estimated from what the step touches: the
// (pixel, Gaussian) pairs the rasterizer blends, the Gaussians it projects, the SSIM filters and
// the Adam update. Counts are per operation class so the report can show where the work goes.
#pragma once

#include <cstddef>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"

namespace gslift::bench {

struct StepFlops {
  double blend_forward =
      0;  // pairs x 40: conic quadratic form, exp, alpha, T, RGB + depth + normal
  double blend_backward = 0;  // pairs x 90: the same chain reversed, plus per-pair gradient sums
  double projection = 0;      // Gaussians x 500: EWA covariance, SH, and their backward
  double ssim = 0;            // 8 separable 11-tap filters over H x W x 3 plus per-pixel terms
  double adam = 0;            // 12 flops per parameter
  double total() const { return blend_forward + blend_backward + projection + ssim + adam; }
};

// Estimate for a step on `view` of `capture` with `model` (rendered once to count the pairs).
StepFlops estimate_step_flops(const GaussianModel& model, const View& view);

// The machine's single-precision peak, measured rather than taken from a data sheet: `threads`
// threads (0 = every hardware thread) each run independent chains of fused multiply-adds at the
// widest vector width this build targets (AVX-512, AVX2 + FMA, or scalar), enough chains to hide
// the FMA latency on two pipes; the best of five timings. The ceiling the blending loops, which
// run at that width, are held against.
struct FmaPeak {
  double gflops = 0;  // 2 flops per lane and FMA
  int lanes = 1;      // single-precision lanes per vector
  int threads = 1;
};
FmaPeak measure_fma_peak(int threads);

}  // namespace gslift::bench
