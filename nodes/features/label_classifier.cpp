#include "nodes/features/label_classifier.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/features/classifier_loss.hpp"
#include "nodes/features/labelled_views.hpp"

namespace gslift {

LabelClassifierResult train_label_classifier(const GaussianModel& model, const Capture& capture,
                                             const LabelMapSet& maps,
                                             const LabelClassifierOptions& o,
                                             const TrainingProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  label_classifier_param_table().validate(o, "features.label_classifier");
  if (model.size() == 0) throw InputError("features.label_classifier: the model has no Gaussians");
  const int dim = o.dim;
  const LabelledViews views =
      render_labelled_views(model, capture, maps, o.min_weight, "features.label_classifier");
  int classes = maps.labels + 1;
  for (const auto& l : views.labels)
    for (const int id : l) classes = std::max(classes, id + 1);

  // Extra parameters: W (classes x dim) then b (classes), torch's Conv2d init
  // U(-1/sqrt(fan_in), 1/sqrt(fan_in)) for both.
  const size_t nw = size_t(classes) * dim;
  std::vector<float> features(model.size() * dim, 0.f), params(nw + classes);
  {
    RandomStream rng(stream_seed(o.seed, "label_classifier.init"));
    const double bound = 1.0 / std::sqrt(double(dim));
    for (float& w : params) w = static_cast<float>(rng.uniform(-bound, bound));
  }
  const size_t nv = views.rows.size();
  const PixelBatchStep step = [&](int it, size_t k, const float* f, const float* w, PixelBatch& b) {
    RandomStream rng(stream_seed(o.seed, "label_classifier.pixels", size_t(it) * nv + k));
    b.view = static_cast<int>(k);
    b.pixels.clear();
    sample_uniform_pixels(o.pixels_per_view, views.labels[k].total(), rng, b.pixels);
    std::vector<int> labels(b.pixels.size());
    for (size_t p = 0; p < b.pixels.size(); ++p)
      labels[p] = views.labels[k].ptr<int>()[b.pixels[p]];
    std::vector<float> rendered(b.pixels.size() * dim);
    views.rows[k].render(f, dim, b.pixels, rendered.data());
    b.grad.resize(rendered.size());
    b.extra_offset = 0;
    b.extra_grad.assign(params.size(), 0.f);
    b.loss = linear_classifier_loss(rendered.data(), static_cast<int>(b.pixels.size()), dim,
                                    labels.data(), w, w + nw, classes, b.grad.data(),
                                    b.extra_grad.data(), b.extra_grad.data() + nw);
  };
  // Gaga's L_3d every kl.interval steps (its iterations count from 1): kl.samples distinct
  // Gaussians (a partial Fisher-Yates shuffle, torch.randperm's draw) and their k nearest centres.
  PixelTrainingExtraTerm neighbour_term;
  std::optional<GaussianNeighbours> tree;
  std::vector<int> order;
  if (o.kl.lambda > 0) {
    tree.emplace(model.means);
    order.resize(model.size());
    std::iota(order.begin(), order.end(), 0);
    neighbour_term = [&](int it, const float* f, const float* w, float* gf, float* gw) {
      if ((it + 1) % o.kl.interval != 0) return 0.0;
      RandomStream rng(stream_seed(o.seed, "label_classifier.kl", size_t(it)));
      const size_t n = order.size(), s = std::min<size_t>(o.kl.samples, n);
      for (size_t i = 0; i < s; ++i) std::swap(order[i], order[i + rng.below(n - i)]);
      const std::vector<int> samples(order.begin(), order.begin() + s);
      const int k = static_cast<int>(std::min<size_t>(o.kl.k, n));
      return neighbour_kl_loss(f, dim, w, w + nw, classes, samples, tree->nearest(samples, k), k,
                               o.kl.lambda, gf, gw, gw + nw);
    };
  }
  PixelTrainingSettings settings;
  settings.iterations = o.iterations;
  settings.dim = dim;
  settings.lr = o.lr;
  settings.extra_lr = o.classifier_lr;
  const PixelTrainingLoss loss = train_pixel_features(views.rows, nv, settings, step, features,
                                                      params, neighbour_term, progress);

  LabelClassifierResult r;
  r.loss_start = loss.start;
  r.loss_end = loss.end;
  r.classifier.dim = dim;
  r.classifier.classes = classes;
  r.classifier.weights.assign(params.begin(), params.begin() + nw);
  r.classifier.bias.assign(params.begin() + nw, params.end());
  r.model = model.with_features(std::move(features), dim);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

const ParamTable<LabelClassifierOptions>& label_classifier_param_table() {
  using O = LabelClassifierOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("iterations", &O::iterations, "Adam steps", 1, 1e7)
          .add("dim", &O::dim, "feature channels per Gaussian (Gaga: 16)", 1, 512)
          .add("lr", &O::lr, "Adam learning rate of the features (Gaga: 2.5e-3)", 1e-9, 10)
          .add("classifier_lr", &O::classifier_lr, "Adam learning rate of the classifier (5e-4)",
               1e-9, 10)
          .add("pixels_per_view", &O::pixels_per_view, "pixels sampled per view and step", 1, 1e7)
          .add("min_weight", &O::min_weight, "blend weights below this are dropped (memory)", 0, 1)
          .nest(&O::kl,
                ParamTable<NeighbourKlOptions>()
                    .add("kl_lambda", &NeighbourKlOptions::lambda,
                         "weight of Gaga's 3D KL neighbour regulariser (its code: 2); 0 = off", 0)
                    .add("kl_k", &NeighbourKlOptions::k,
                         "nearest Gaussians per sample, itself included (Gaga: 5)", 1, 1000)
                    .add("kl_interval", &NeighbourKlOptions::interval,
                         "the regulariser joins every this many steps (Gaga: 5)", 1, 1e6)
                    .add("kl_samples", &NeighbourKlOptions::samples,
                         "Gaussians sampled per regularised step (Gaga: 1000)", 1, 1e7));
  return table;
}

}  // namespace gslift
