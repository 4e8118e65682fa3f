#include "nodes/features/pixel_feature_training.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "nodes/splat/adam.hpp"
#include "nodes/splat/pixel_rows.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

PixelRows render_pixel_rows(const GaussianModel& model, const Camera& camera, const Pose& pose,
                            float min_weight) {
  RenderSettings weights_only;
  weights_only.rgb = false;
  weights_only.alpha = true;
  return PixelRows(render(model, camera, pose, weights_only), min_weight);
}

PixelTrainingLoss train_pixel_features(const std::vector<PixelRows>& rows, size_t batches,
                                       const PixelTrainingSettings& s, const PixelBatchStep& step,
                                       std::vector<float>& features, std::vector<float>& extras,
                                       const PixelTrainingExtraTerm& extra_term,
                                       const TrainingProgress& progress) {
  const int dim = s.dim;
  const size_t n = features.size() / dim;
  std::vector<float> grad(features.size());
  std::vector<float> extra_grad(extras.size());
  AdamGroup adam(dim);
  AdamGroup extra_adam(1);
  std::vector<PixelBatch> out(batches);
  PixelTrainingLoss loss;

  for (int it = 0; it < s.iterations; ++it) {
    tbb::parallel_for(size_t(0), batches,
                      [&](size_t b) { step(it, b, features.data(), extras.data(), out[b]); });
    // Fixed batch order: the sums do not depend on the thread count.
    double total = 0;
    std::fill(grad.begin(), grad.end(), 0.f);
    std::fill(extra_grad.begin(), extra_grad.end(), 0.f);
    for (size_t b = 0; b < batches; ++b) {
      const PixelBatch& batch = out[b];
      total += batch.loss;
      rows[batch.view].backward(batch.pixels, batch.grad.data(), dim, grad.data());
      for (size_t k = 0; k < batch.extra_grad.size(); ++k)
        extra_grad[batch.extra_offset + k] += batch.extra_grad[k];
    }
    total /= batches;
    if (extra_term)
      total += extra_term(it, features.data(), extras.data(), grad.data(), extra_grad.data());
    if (it == 0) loss.start = total;
    loss.end = total;
    adam.step(features.data(), grad.data(), n, static_cast<float>(s.lr));
    if (!extras.empty())
      extra_adam.step(extras.data(), extra_grad.data(), extras.size(),
                      static_cast<float>(s.extra_lr));
    if (progress) progress({it + 1, s.iterations, total});
  }
  return loss;
}

}  // namespace gslift
