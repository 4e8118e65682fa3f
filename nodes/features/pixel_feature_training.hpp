// The training loop shared by every per-Gaussian feature objective on frozen geometry (LangOR's
// contrastive features, Proto-SaGa's per-view classifiers (Eq. 6-8), Gaga's label classifier,
// SAGA's correspondence features): each training view's blend weights are recorded once as
// PixelRows; every iteration a caller-supplied step samples pixels for each of its batches,
// renders their features F(p) = sum_i w_i f_i from the rows and returns its loss and dL/dF(p);
// the gradients go back to the Gaussians through the same weights (W_S^T dL/dF_S), and Adam takes
// one step on the features and, optionally, on extra parameters (classifier weights) with their
// own learning rate.
//
// Deterministic for a fixed seed at any thread count: batches run in parallel but write only
// their own PixelBatch, and their gradients are scattered sequentially in batch order. A step
// that samples must seed its RNG by (seed, iteration, batch), never a thread id.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "base/training_step.hpp"
#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/pixel_rows.hpp"

namespace gslift {

// The blend weights of `model` seen from one camera, as PixelRows without the pairs below
// min_weight (one forward pass, weights only).
PixelRows render_pixel_rows(const GaussianModel& model, const Camera& camera, const Pose& pose,
                            float min_weight);

// What one batch of one iteration produced: its view (an index into the trainer's rows), the
// sampled pixels (row-major), dL/dF at them (pixels x dim) and its loss; optionally a gradient
// for the extra parameters, added at extra_offset (e.g. one view's classifier block).
struct PixelBatch {
  int view = 0;
  std::vector<uint32_t> pixels;
  std::vector<float> grad;
  double loss = 0;
  size_t extra_offset = 0;
  std::vector<float> extra_grad;
};

struct PixelTrainingSettings {
  int iterations = 1;
  int dim = 16;
  double lr = 1e-3;        // Adam rate of the features
  double extra_lr = 1e-3;  // Adam rate of the extra parameters (unused without them)
};

// Fills `batch` (cleared by the caller's own logic: it is reused across iterations) for batch b
// of iteration `it`, with the current features (N x dim) and extra parameters.
using PixelBatchStep = std::function<void(int it, size_t b, const float* features,
                                          const float* extras, PixelBatch& batch)>;
// Called once per iteration after the batches are scattered, before the Adam step: may add to
// the gradients of the features and extras (a regulariser over the Gaussians) and returns the
// loss it adds to the iteration's.
using PixelTrainingExtraTerm = std::function<double(
    int it, const float* features, const float* extras, float* grad_features, float* grad_extras)>;

struct PixelTrainingLoss {
  // Mean batch loss (plus the extra term) at the first iteration (before any update) and the last.
  double start = 0;
  double end = 0;
};

// Runs settings.iterations steps over `batches` batches per iteration, updating features (N x dim
// row-major) and extras in place. progress (steps done, total, the
// iteration's loss) runs after each iteration and may throw to
// stop the run.
PixelTrainingLoss train_pixel_features(const std::vector<PixelRows>& rows, size_t batches,
                                       const PixelTrainingSettings& settings,
                                       const PixelBatchStep& step, std::vector<float>& features,
                                       std::vector<float>& extras,
                                       const PixelTrainingExtraTerm& extra_term = {},
                                       const TrainingProgress& progress = {});

}  // namespace gslift
