#include "nodes/features/contrastive_features.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/features/contrastive_loss.hpp"
#include "nodes/features/pixel_feature_training.hpp"

namespace gslift {
namespace {

// One mask of one training view: the pixels inside it (row-major indices) and the mask itself,
// for the outside test.
struct TrainingMask {
  int rows = 0;  // index into view_rows
  cv::Mat1b pixels;
  std::vector<uint32_t> inside;
};

void validate(const GaussianModel& model, const ContrastiveOptions& o) {
  if (model.size() == 0) throw InputError("features.contrastive: the model has no Gaussians");
  if (o.iterations < 1 || o.dim < 1 || o.pixels_per_iteration < 1 || !(o.lr > 0) ||
      !(o.lambda >= 0) || !(o.init_std > 0) || !(o.min_weight >= 0))
    throw InputError(
        "features.contrastive: iterations, dim, pixels_per_iteration, lr and init_std must be "
        "positive, lambda and min_weight non-negative");
}

// n pixels uniformly inside the mask, then up to n uniformly outside it (rejection sampling over
// the view; none when the mask covers the whole view). Returns the outside count.
int sample_pixels(const TrainingMask& m, int n, RandomStream& rng, std::vector<uint32_t>& pixels) {
  for (int k = 0; k < n; ++k) pixels.push_back(m.inside[rng.below(m.inside.size())]);
  const size_t total = m.pixels.total();
  if (m.inside.size() == total) return 0;
  int out = 0;
  // The expected number of draws is n total / (total - |M|); the cap only guards masks that
  // cover almost everything.
  for (int tries = 0; out < n && tries < 64 * n; ++tries) {
    const size_t p = rng.below(total);
    if (m.pixels.data[p]) continue;
    pixels.push_back(static_cast<uint32_t>(p));
    ++out;
  }
  return out;
}

}  // namespace

ContrastiveResult train_contrastive_features(const GaussianModel& model, const Capture& capture,
                                             const MaskSet& masks, const ContrastiveOptions& o,
                                             const ContrastiveProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  validate(model, o);
  const int dim = o.dim;

  // Render view_rows of the training views that have masks, and their non-empty masks.
  std::vector<PixelRows> view_rows;
  std::vector<TrainingMask> training;
  for (const MaskView& mv : training_mask_views(capture, masks)) {
    const ViewMasks& vm = masks.views[mv.mask_view];
    const View& view = capture.views[mv.capture_view];
    const int rows_index = static_cast<int>(view_rows.size());
    for (size_t k = 0; k < vm.masks.size(); ++k) {
      const cv::Mat1b& px = vm.masks[k].pixels;
      TrainingMask m;
      m.rows = rows_index;
      m.pixels = px.isContinuous() ? px : px.clone();
      for (size_t p = 0; p < m.pixels.total(); ++p)
        if (m.pixels.data[p]) m.inside.push_back(static_cast<uint32_t>(p));
      if (!m.inside.empty()) training.push_back(std::move(m));
    }
    if (!training.empty() && training.back().rows == rows_index)
      view_rows.push_back(
          render_pixel_rows(model, view.camera, view.pose, static_cast<float>(o.min_weight)));
  }
  if (training.empty())
    throw InputError("features.contrastive: no training view of capture '" + capture.name +
                     "' has a non-empty mask");

  ContrastiveResult result;
  result.masks = static_cast<int>(training.size());
  for (const auto& c : view_rows) result.cache_bytes += c.bytes();

  std::vector<float> features(model.size() * dim);
  {
    RandomStream rng(stream_seed(o.seed, "contrastive.init"));
    for (float& f : features) f = static_cast<float>(rng.normal(0.0, o.init_std));
  }
  // One batch per (iteration, mask): pixels inside and outside the mask, LangOR Eq. 3.
  const PixelBatchStep step = [&](int it, size_t k, const float* f, const float*, PixelBatch& s) {
    const TrainingMask& m = training[k];
    // One stream per (iteration, mask), numbered row by row.
    RandomStream rng(stream_seed(o.seed, "contrastive.pixels", it * training.size() + k));
    s.view = m.rows;
    s.pixels.clear();
    const int n_out = sample_pixels(m, o.pixels_per_iteration, rng, s.pixels);
    const int n_in = o.pixels_per_iteration;
    std::vector<float> rendered(s.pixels.size() * dim);
    view_rows[m.rows].render(f, dim, s.pixels, rendered.data());
    s.grad.resize(rendered.size());
    s.loss =
        mask_contrastive_loss(rendered.data(), n_in, rendered.data() + size_t(n_in) * dim, n_out,
                              dim, o.lambda, s.grad.data(), s.grad.data() + size_t(n_in) * dim);
  };
  PixelTrainingSettings settings;
  settings.iterations = o.iterations;
  settings.dim = dim;
  settings.lr = o.lr;
  std::vector<float> no_extras;
  const PixelTrainingLoss loss = train_pixel_features(view_rows, training.size(), settings, step,
                                                      features, no_extras, {}, progress);
  result.loss_start = loss.start;
  result.loss_end = loss.end;

  result.model = model.with_features(std::move(features), dim);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

const ParamTable<ContrastiveOptions>& contrastive_param_table() {
  using O = ContrastiveOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("iterations", &O::iterations, "Adam steps (LangOR: 300)", 1, 1e6)
          .add("lambda", &O::lambda, "weight of the outside-mask repulsion (LangOR: 0.2)", 0)
          .add("dim", &O::dim, "feature channels per Gaussian", 1, 512)
          .add("lr", &O::lr, "Adam learning rate of the features", 1e-9, 10)
          .add("pixels_per_iteration", &O::pixels_per_iteration,
               "pixels sampled inside each mask per step, and as many outside", 1, 1e6)
          .add("init_std", &O::init_std, "standard deviation of the random initial features", 1e-9,
               100)
          .add("min_weight", &O::min_weight,
               "blend weights below this are dropped from the stored rows (memory)", 0, 1);
  return table;
}

}  // namespace gslift
