// What a training loop says after each step, for the progress line (issue 32: "step / total, loss,
// train PSNR and time left"): the algorithms fill it, runtime/progress.hpp shows it. Plain data in
// base/ so that both the node families and the runtime may include it.
#pragma once

#include <functional>
#include <limits>

namespace gslift {

struct TrainingStep {
  int step = 0;                                            // steps done, 1..total
  int total = 0;                                           // steps planned
  double loss = std::numeric_limits<double>::quiet_NaN();  // the step's total loss
  // PSNR (dB) of the step's render against its training view; NaN for loops that render nothing.
  double train_psnr = std::numeric_limits<double>::quiet_NaN();
};

// Called after every step; may throw (gslift::Cancelled) to stop the loop.
using TrainingProgress = std::function<void(const TrainingStep&)>;

}  // namespace gslift
