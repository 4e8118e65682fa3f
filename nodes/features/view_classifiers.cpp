#include "nodes/features/view_classifiers.hpp"

#include <algorithm>
#include <chrono>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/features/classifier_loss.hpp"
#include "nodes/features/labelled_views.hpp"

namespace gslift {
namespace {
// Classifier rows start as N(0, 0.01^2) draws: Eq. 6 divides by |w_c|, so only their directions
// matter, and a small norm lets the Adam steps of 5e-4 turn them quickly.
constexpr double kClassifierInitStd = 0.01;
}  // namespace

ViewClassifierResult train_view_classifiers(const GaussianModel& model, const Capture& capture,
                                            const LabelMapSet& partitions,
                                            const ViewClassifierOptions& o,
                                            const std::function<void(int, int)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  view_classifier_param_table().validate(o, "features.view_classifiers");
  if (model.size() == 0) throw InputError("features.view_classifiers: the model has no Gaussians");
  const int dim = o.dim;
  const LabelledViews views =
      render_labelled_views(model, capture, partitions, o.min_weight, "features.view_classifiers");

  // Extra parameters, rows of dim floats: with shared_background one class-0 ("no mask") row
  // for every view first; then per view its own class-0 row (without sharing) and the rows of
  // its classes 1..L_k.
  const size_t nv = views.rows.size();
  std::vector<int> classes(nv);
  std::vector<size_t> background_row(nv), first_row(nv);
  size_t rows = o.shared_background ? 1 : 0;
  for (size_t k = 0; k < nv; ++k) {
    int top = 0;
    for (const int id : views.labels[k]) top = std::max(top, id);
    classes[k] = top + 1;
    background_row[k] = o.shared_background ? 0 : rows++;
    first_row[k] = rows;
    rows += top;
  }
  auto row_of = [&](size_t k, int c) { return c > 0 ? first_row[k] + c - 1 : background_row[k]; };
  std::vector<float> features(model.size() * dim), weights(rows * dim);
  {
    RandomStream rng(stream_seed(o.seed, "view_classifiers.init"));
    for (float& f : features) f = static_cast<float>(rng.normal(0.0, o.init_std));
    for (float& w : weights) w = static_cast<float>(rng.normal(0.0, kClassifierInitStd));
  }

  // One batch per (iteration, view): uniform pixels, Eq. 6-7 against the view's SAM ids.
  const PixelBatchStep step = [&](int it, size_t k, const float* f, const float* w, PixelBatch& b) {
    RandomStream rng(stream_seed(o.seed, "view_classifiers.pixels", size_t(it) * nv + k));
    b.view = static_cast<int>(k);
    b.pixels.clear();
    sample_uniform_pixels(o.pixels_per_view, views.labels[k].total(), rng, b.pixels);
    std::vector<int> labels(b.pixels.size());
    for (size_t p = 0; p < b.pixels.size(); ++p)
      labels[p] = views.labels[k].ptr<int>()[b.pixels[p]];
    std::vector<float> rendered(b.pixels.size() * dim);
    views.rows[k].render(f, dim, b.pixels, rendered.data());
    b.grad.resize(rendered.size());
    // The view's classifier gathered into classes x dim, its gradient scattered back.
    std::vector<float> local(size_t(classes[k]) * dim), local_grad(local.size(), 0.f);
    for (int c = 0; c < classes[k]; ++c)
      std::copy_n(w + row_of(k, c) * dim, dim, local.begin() + size_t(c) * dim);
    b.loss = cosine_classifier_loss(rendered.data(), static_cast<int>(b.pixels.size()), dim,
                                    labels.data(), local.data(), classes[k], o.tau, b.grad.data(),
                                    local_grad.data());
    b.extra_offset = 0;
    b.extra_grad.assign(weights.size(), 0.f);
    for (int c = 0; c < classes[k]; ++c)
      std::copy_n(local_grad.begin() + size_t(c) * dim, dim,
                  b.extra_grad.begin() + row_of(k, c) * dim);
  };
  PixelTrainingSettings settings;
  settings.iterations = o.iterations;
  settings.dim = dim;
  settings.lr = o.lr;
  settings.extra_lr = o.classifier_lr;
  const PixelTrainingLoss loss =
      train_pixel_features(views.rows, nv, settings, step, features, weights, {}, progress);

  ViewClassifierResult r;
  r.loss_start = loss.start;
  r.loss_end = loss.end;
  r.cache_bytes = views.bytes();
  r.classifiers.dim = dim;
  r.classifiers.tau = o.tau;
  for (size_t k = 0; k < nv; ++k) {
    ViewClassifier c;
    c.view = capture.views[views.capture_views[k]].name;
    c.classes = classes[k];
    c.weights.resize(size_t(classes[k]) * dim);
    for (int cl = 0; cl < classes[k]; ++cl)
      std::copy_n(weights.begin() + row_of(k, cl) * dim, dim, c.weights.begin() + size_t(cl) * dim);
    r.classifiers.views.push_back(std::move(c));
  }
  r.model = model.with_features(std::move(features), dim);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

const ParamTable<ViewClassifierOptions>& view_classifier_param_table() {
  using O = ViewClassifierOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("iterations", &O::iterations, "Adam steps", 1, 1e7)
          .add("dim", &O::dim, "feature channels per Gaussian (D = 16)", 1, 512)
          .add("tau", &O::tau, "temperature of the cosine logits (Eq. 6: 10)", 1e-6, 1e6)
          .add("lr", &O::lr, "Adam learning rate of the features (2.5e-3)", 1e-9, 10)
          .add("classifier_lr", &O::classifier_lr, "Adam learning rate of the classifiers (5e-4)",
               1e-9, 10)
          .add("pixels_per_view", &O::pixels_per_view, "pixels sampled per view and step", 1, 1e7)
          .add("init_std", &O::init_std,
               "standard deviation of the random initial features (0: zeros, as Gaga)", 0, 100)
          .add("min_weight", &O::min_weight, "blend weights below this are dropped (memory)", 0, 1)
          .add("shared_background", &O::shared_background,
               "one class-0 (no SAM mask) row shared by every view's classifier");
  return table;
}

}  // namespace gslift
