#include "nodes/features/pixel_feature_training.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

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
    // The features' gradient in blocks of Gaussian ids, a task each: every block zeroes its rows
    // and scans all batches in their fixed order, adding only to its own rows, so each row's sum
    // runs in the order of one serial pass (the same result at any thread count) and no two tasks
    // write the same row. (One thread summing all batches left the other idle: about 0.5 s of
    // LangOR's main job.)
    const size_t blocks = size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    tbb::parallel_for(size_t(0), blocks, [&](size_t k) {
      const size_t begin = n * k / blocks, end = n * (k + 1) / blocks;
      std::fill(grad.begin() + begin * dim, grad.begin() + end * dim, 0.f);
      for (size_t b = 0; b < batches; ++b)
        rows[out[b].view].backward(out[b].pixels, out[b].grad.data(), dim, grad.data(),
                                   uint32_t(begin), uint32_t(end));
    });
    // Fixed batch order: the sums do not depend on the thread count.
    double total = 0;
    std::fill(extra_grad.begin(), extra_grad.end(), 0.f);
    for (size_t b = 0; b < batches; ++b) {
      const PixelBatch& batch = out[b];
      total += batch.loss;
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
