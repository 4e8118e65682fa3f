#include "nodes/features/correspondence_features.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/features/correspondence_loss.hpp"
#include "nodes/features/pixel_feature_training.hpp"
#include "nodes/features/scale_gated_features.hpp"

namespace gslift {

CorrespondenceResult train_correspondence_features(const GaussianModel& model,
                                                   const Capture& capture, const MaskSet& masks,
                                                   const CorrespondenceOptions& o,
                                                   const TrainingProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  correspondence_param_table().validate(o, "features.correspondence");
  if (o.variant == AffinityVariant::ScaleGated)
    return train_scale_gated_features(model, capture, masks, o, progress);
  if (model.size() == 0) throw InputError("features.correspondence: the model has no Gaussians");
  CorrespondenceResult result;
  std::vector<PixelRows> rows;
  std::vector<MaskedPixels> views;
  for (const MaskView& mv : training_mask_views(capture, masks)) {
    const ViewMasks& vm = masks.views[mv.mask_view];
    const View& view = capture.views[mv.capture_view];
    MaskedPixels m = masked_pixels(vm, size_t(view.camera.width) * view.camera.height);
    if (m.covered.size() < 2) continue;
    result.masks += static_cast<int>(vm.masks.size());
    result.cache_bytes += m.membership.bits.size() * sizeof(uint64_t);
    views.push_back(std::move(m));
    rows.push_back(
        render_pixel_rows(model, view.camera, view.pose, static_cast<float>(o.min_weight)));
    result.cache_bytes += rows.back().bytes();
  }
  if (views.empty())
    throw InputError("features.correspondence: no training view of capture '" + capture.name +
                     "' has pixels covered by a mask");
  result.views = static_cast<int>(views.size());

  const int dim = o.dim;
  const bool normalize = o.normalize_gaussians;
  std::vector<float> features(model.size() * dim);
  RandomStream init(stream_seed(o.seed, "correspondence.init"));
  for (float& f : features) f = static_cast<float>(init.normal(0.0, o.init_std));
  std::vector<float> no_extras;

  const size_t batches = static_cast<size_t>(o.views_per_iteration);
  // With normalize_gaussians the batches render unit features u = f / |f|, computed once per
  // iteration by whichever batch needs them first (the same values whoever computes them), and
  // the gradient is taken through the normalisation before the Adam step.
  std::vector<float> unit(normalize ? features.size() : 0), norms(normalize ? model.size() : 0);
  std::mutex unit_mutex;
  int unit_iteration = -1;
  auto rendered_attributes = [&](int it, const float* current) -> const float* {
    if (!normalize) return current;
    std::lock_guard<std::mutex> lock(unit_mutex);
    if (unit_iteration != it) {
      tbb::parallel_for(size_t(0), model.size(), [&](size_t g) {
        double s = 0;
        for (int c = 0; c < dim; ++c) s += double(current[g * dim + c]) * current[g * dim + c];
        norms[g] = static_cast<float>(std::max(std::sqrt(s), 1e-12));
        for (int c = 0; c < dim; ++c) unit[g * dim + c] = current[g * dim + c] / norms[g];
      });
      unit_iteration = it;
    }
    return unit.data();
  };
  // dL/df = (dL/du - <dL/du, u> u) / |f|, in place.
  auto through_normalisation = [&](int, const float*, const float*, float* grad, float*) {
    tbb::parallel_for(size_t(0), model.size(), [&](size_t g) {
      float along = 0;
      for (int c = 0; c < dim; ++c) along += grad[g * dim + c] * unit[g * dim + c];
      for (int c = 0; c < dim; ++c)
        grad[g * dim + c] = (grad[g * dim + c] - along * unit[g * dim + c]) / norms[g];
    });
    return 0.0;
  };
  auto step = [&](int it, size_t b, const float* raw, const float*, PixelBatch& batch) {
    const float* current = rendered_attributes(it, raw);
    RandomStream rng(stream_seed(o.seed, "correspondence.pixels", it * batches + b));
    batch.view = static_cast<int>(rng.below(views.size()));
    const MaskedPixels& v = views[batch.view];
    batch.pixels.resize(o.pixels_per_iteration);
    for (uint32_t& p : batch.pixels) p = v.covered[rng.below(v.covered.size())];
    Eigen::MatrixXf rendered(dim, batch.pixels.size());  // column-major: one column per pixel
    rows[batch.view].render(current, dim, batch.pixels, rendered.data());
    Eigen::MatrixXf grad;
    batch.loss = correspondence_loss(rendered.transpose(),
                                     correspondence_kernel(v.membership, batch.pixels), &grad);
    batch.grad.resize(grad.size());
    Eigen::Map<Eigen::MatrixXf>(batch.grad.data(), dim, grad.rows()) = grad.transpose();
  };
  PixelTrainingSettings s;
  s.iterations = o.iterations;
  s.dim = dim;
  s.lr = o.lr;
  const PixelTrainingLoss loss = train_pixel_features(
      rows, batches, s, step, features, no_extras,
      normalize ? PixelTrainingExtraTerm(through_normalisation) : PixelTrainingExtraTerm(),
      progress);
  result.loss_start = loss.start;
  result.loss_end = loss.end;
  result.model = model.with_features(std::move(features), dim);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

const ParamTable<CorrespondenceOptions>& correspondence_param_table() {
  using O = CorrespondenceOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("variant", &O::variant, affinity_variant_names(),
               "correspondence (paper) or scale_gated (the public v2 code's loss)")
          .add("iterations", &O::iterations, "Adam steps", 1, 1e7)
          .add("dim", &O::dim, "feature channels per Gaussian (SAGA: 32)", 1, 512)
          .add("lr", &O::lr, "Adam learning rate of the features (SAGA: 2.5e-3)", 1e-9, 10)
          .add("pixels_per_iteration", &O::pixels_per_iteration,
               "pixels sampled per view and step, every two paired (SAGA: 1000 rays)", 2, 1e5)
          .add("views_per_iteration", &O::views_per_iteration, "views drawn per step", 1, 1e4)
          .add("init_std", &O::init_std, "standard deviation of the random initial features", 1e-9,
               100)
          .add("normalize_gaussians", &O::normalize_gaussians,
               "render L2-normalised per-Gaussian features (SAGA code: norm_point_features)")
          .add("min_weight", &O::min_weight,
               "blend weights below this are dropped from the stored rows (memory)", 0, 1)
          .add("smooth_k", &O::smooth_k,
               "scale_gated: nearest Gaussians averaged by the feature smoothing (1 = none)", 1,
               256)
          .add("norm_weight", &O::norm_weight,
               "scale_gated: weight of the rendered-feature-norm regulariser (SAGA rfn)", 0, 1e3)
          .add("sampled_scales", &O::sampled_scales,
               "scale_gated: mask scales drawn per step besides the largest and smallest", 1, 64)
          .add("gate_scale", &O::gate_scale,
               "scale_gated: the quantile-space scale (0..1) the output features are gated at", 0,
               1)
          .add("scale_swap_axes", &O::scale_swap_axes,
               "scale_gated: back-project mask scales with SAGA get_scale.py's row/column swap");
  return table;
}

const EnumNames<AffinityVariant>& affinity_variant_names() {
  static const EnumNames<AffinityVariant> names = {
      {AffinityVariant::Correspondence, "correspondence"},
      {AffinityVariant::ScaleGated, "scale_gated"}};
  return names;
}

}  // namespace gslift
