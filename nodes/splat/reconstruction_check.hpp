// When a reconstruction is no result: no Gaussian left, or a train PSNR under a floor (a model
// that explains the training views no better than a flat colour would). splat.reconstruct fails
// with the cause instead of handing an empty or black scene downstream as "ok".
#pragma once

#include <string>

#include "nodes/splat/reconstruct.hpp"

namespace gslift {

// Far below what working reconstructions reach (issue 29: 21.8 to 24.2 dB held-out on the fox,
// 3DMatch and Replica room0 at 100 steps) and above the broken one (room0 at 500 steps: 4.1 dB
// train PSNR, all-black renders).
constexpr double kDefaultMinTrainPsnr = 10.0;

// Empty when `r` is a result; otherwise why not, naming the step and the pruning that emptied
// the model when one did. `min_train_psnr` 0 turns the PSNR floor off; a NaN PSNR (no training
// view) is not judged.
std::string reconstruction_failure(const ReconstructResult& r, double min_train_psnr);

}  // namespace gslift
