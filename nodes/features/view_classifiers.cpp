#include "nodes/features/view_classifiers.hpp"

#include <algorithm>
#include <chrono>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/features/classifier_loss.hpp"
#include "nodes/features/labelled_views.hpp"
#include "nodes/splat/adam.hpp"
#include "nodes/splat/feature_objective.hpp"

namespace gslift {
namespace {
// Classifier rows start as N(0, 0.01^2) draws: Eq. 6 divides by |w_c|, so only their directions
// matter, and a small norm lets the Adam steps of 5e-4 turn them quickly.
constexpr double kClassifierInitStd = 0.01;

// Where each view's classifier rows lie in the one parameter array (rows of dim floats): with
// shared_background one class-0 ("no mask") row for every view first; then per view its own
// class-0 row (without sharing) and the rows of its classes 1..L_k.
struct ClassifierLayout {
  std::vector<int> classes;  // per view: L_k + 1
  std::vector<size_t> background_row, first_row;
  size_t rows = 0;
  size_t row_of(size_t k, int c) const { return c > 0 ? first_row[k] + c - 1 : background_row[k]; }
};

ClassifierLayout classifier_layout(const std::vector<cv::Mat1i>& labels, bool shared_background) {
  ClassifierLayout l;
  const size_t nv = labels.size();
  l.classes.resize(nv);
  l.background_row.resize(nv);
  l.first_row.resize(nv);
  l.rows = shared_background ? 1 : 0;
  for (size_t k = 0; k < nv; ++k) {
    int top = 0;
    for (const int id : labels[k]) top = std::max(top, id);
    l.classes[k] = top + 1;
    l.background_row[k] = shared_background ? 0 : l.rows++;
    l.first_row[k] = l.rows;
    l.rows += top;
  }
  return l;
}

// Eq. 6-7 at n rendered pixels of view k: the view's classifier gathered into classes x dim,
// dL/dF written to grad (n x dim), its own gradient scattered and ADDED to weight_grad.
double view_batch_loss(const ClassifierLayout& l, size_t k, const float* rendered, int n,
                       const int* labels, const float* weights, int dim, double tau, float* grad,
                       float* weight_grad) {
  const int classes = l.classes[k];
  std::vector<float> local(size_t(classes) * dim), local_grad(local.size(), 0.f);
  for (int c = 0; c < classes; ++c)
    std::copy_n(weights + l.row_of(k, c) * dim, dim, local.begin() + size_t(c) * dim);
  const double loss = cosine_classifier_loss(rendered, n, dim, labels, local.data(), classes, tau,
                                             grad, local_grad.data());
  for (int c = 0; c < classes; ++c) {
    float* to = weight_grad + l.row_of(k, c) * dim;
    for (int d = 0; d < dim; ++d) to[d] += local_grad[size_t(c) * dim + d];
  }
  return loss;
}

ViewClassifiers collect_classifiers(const ClassifierLayout& l, const std::vector<float>& weights,
                                    const LabelledViews& views, const Capture& capture,
                                    const ViewClassifierOptions& o) {
  ViewClassifiers out;
  out.dim = o.dim;
  out.tau = o.tau;
  for (size_t k = 0; k < l.classes.size(); ++k) {
    ViewClassifier c;
    c.view = capture.views[views.capture_views[k]].name;
    c.classes = l.classes[k];
    c.weights.resize(size_t(c.classes) * o.dim);
    for (int cl = 0; cl < c.classes; ++cl)
      std::copy_n(weights.begin() + l.row_of(k, cl) * o.dim, o.dim,
                  c.weights.begin() + size_t(cl) * o.dim);
    out.views.push_back(std::move(c));
  }
  return out;
}

}  // namespace

const EnumNames<FeatureTraining>& feature_training_names() {
  static const EnumNames<FeatureTraining> names = {{FeatureTraining::Frozen, "frozen"},
                                                   {FeatureTraining::Joint, "joint"}};
  return names;
}

ViewClassifierResult train_view_classifiers(const GaussianModel& model, const Capture& capture,
                                            const LabelMapSet& partitions,
                                            const ViewClassifierOptions& o,
                                            const TrainingProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  view_classifier_param_table().validate(o, "features.view_classifiers");
  if (model.size() == 0) throw InputError("features.view_classifiers: the model has no Gaussians");
  const int dim = o.dim;
  const LabelledViews views =
      render_labelled_views(model, capture, partitions, o.min_weight, "features.view_classifiers");
  const size_t nv = views.rows.size();
  const ClassifierLayout layout = classifier_layout(views.labels, o.shared_background);
  std::vector<float> features(model.size() * dim), weights(layout.rows * dim);
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
    b.extra_offset = 0;
    b.extra_grad.assign(weights.size(), 0.f);
    b.loss = view_batch_loss(layout, k, rendered.data(), static_cast<int>(b.pixels.size()),
                             labels.data(), w, dim, o.tau, b.grad.data(), b.extra_grad.data());
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
  r.classifiers = collect_classifiers(layout, weights, views, capture, o);
  r.model = model.with_features(std::move(features), dim);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

ViewClassifierResult train_view_classifiers_jointly(const Capture& capture,
                                                    const LabelMapSet& partitions,
                                                    const ViewClassifierOptions& o,
                                                    const TrainingProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  view_classifier_param_table().validate(o, "features.view_classifiers");
  const int dim = o.dim;
  const LabelledViews views =
      labelled_training_views(capture, partitions, "features.view_classifiers");
  const ClassifierLayout layout = classifier_layout(views.labels, o.shared_background);
  std::vector<float> weights(layout.rows * dim), weight_grad(weights.size(), 0.f);
  {
    RandomStream rng(stream_seed(o.seed, "view_classifiers.init"));
    for (float& w : weights) w = static_cast<float>(rng.normal(0.0, kClassifierInitStd));
  }
  // Capture view -> index into `views` (-1: no partition, no L_CE at that view).
  std::vector<int> slot(capture.views.size(), -1);
  for (size_t k = 0; k < views.capture_views.size(); ++k)
    slot[views.capture_views[k]] = static_cast<int>(k);

  FeatureObjective objective;
  objective.dim = dim;
  objective.weight = o.lambda_ce;
  objective.lr = o.lr;
  objective.initialise = [&](size_t, std::vector<float>& features) {
    RandomStream rng(stream_seed(o.seed, "view_classifiers.joint_features"));
    for (float& f : features) f = static_cast<float>(rng.normal(0.0, o.init_std));
  };
  double first_loss = -1;
  // Eq. 6-7 at uniform pixels of the step's render, drawn before it so that only they get
  // features; coarse steps render at a lower resolution than the partition, whose label is read at
  // the pixel centre (nearest).
  std::vector<uint32_t> pixels;
  objective.pixels = [&](int step, int view, int width, int height, std::vector<uint32_t>& out) {
    pixels.clear();
    if (slot[view] >= 0) {
      RandomStream rng(stream_seed(o.seed, "view_classifiers.joint_pixels", size_t(step)));
      sample_uniform_pixels(o.pixels_per_view, size_t(width) * height, rng, pixels);
    }
    out = pixels;
  };
  objective.loss = [&](int, int view, int width, int height, const float* rendered, float* grad) {
    const int k = slot[view];
    if (k < 0) return 0.0;
    const cv::Mat1i& map = views.labels[k];
    const int n = static_cast<int>(pixels.size());
    std::vector<int> labels(n);
    std::vector<float> batch(size_t(n) * dim), batch_grad(batch.size());
    for (int i = 0; i < n; ++i) {
      const int x = static_cast<int>(pixels[i] % width), y = static_cast<int>(pixels[i] / width);
      const int mx = std::min(
          map.cols - 1, static_cast<int>((2 * x + 1) * int64_t(map.cols) / (2 * int64_t(width))));
      const int my = std::min(
          map.rows - 1, static_cast<int>((2 * y + 1) * int64_t(map.rows) / (2 * int64_t(height))));
      labels[i] = map(my, mx);
      std::copy_n(rendered + size_t(pixels[i]) * dim, dim, batch.begin() + size_t(i) * dim);
    }
    const double loss = view_batch_loss(layout, k, batch.data(), n, labels.data(), weights.data(),
                                        dim, o.tau, batch_grad.data(), weight_grad.data());
    for (int i = 0; i < n; ++i)
      for (int d = 0; d < dim; ++d)
        grad[size_t(pixels[i]) * dim + d] += batch_grad[size_t(i) * dim + d];
    if (first_loss < 0) first_loss = loss;
    return loss;
  };
  AdamGroup classifier_adam(1);
  objective.update = [&](int) {
    classifier_adam.step(weights.data(), weight_grad.data(), weights.size(),
                         static_cast<float>(o.classifier_lr));
    std::fill(weight_grad.begin(), weight_grad.end(), 0.f);
  };

  ReconstructOptions recon = o.recon;
  recon.seed = o.seed;
  ReconstructResult rec = reconstruct(
      capture, recon,
      [&](const TrainingStep& step, size_t) {
        if (progress) progress(step);
      },
      &objective);

  ViewClassifierResult r;
  r.loss_start = std::max(first_loss, 0.0);
  r.loss_end = rec.final_loss.features;
  r.classifiers = collect_classifiers(layout, weights, views, capture, o);
  r.model = std::move(rec.model);
  r.recon = std::move(rec);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

namespace {

// splat.reconstruct's params joint training exposes: the main ones, then those a recipe sets.
std::vector<std::string> joint_recon_params() {
  std::vector<std::string> names = {"iterations",    "background",      "sh_degree", "depth_weight",
                                    "normal_weight", "coarse_fraction", "densify"};
  for (const auto& name : recipe_param_names())
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  return names;
}

}  // namespace

const ParamTable<ViewClassifierOptions>& view_classifier_param_table() {
  using O = ViewClassifierOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("training", &O::training, feature_training_names(),
               "frozen: on the model input's geometry (appendix variant); joint: reconstructs "
               "the capture with L_rec + lambda_ce L_CE (Eq. 8, the paper's main variant; the "
               "recon_* params are splat.reconstruct's; no model input)")
          .add("iterations", &O::iterations, "Adam steps (frozen)", 1, 1e7)
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
               "one class-0 (no SAM mask) row shared by every view's classifier")
          .add("lambda_ce", &O::lambda_ce, "joint: weight of L_CE against L_rec (Eq. 8: 0.05)", 0)
          // The reconstruction params joint training exposes: splat.reconstruct's declarations
          // and defaults, named recon_<its name>, its recipes and the params they set; the rest
          // keep those defaults.
          .add("recon_recipe", &O::recon_recipe, recipe_names(),
               "joint: splat.reconstruct's recipe, setting the recon_* params it names where the "
               "graph leaves them unset")
          .presets(recipe_presets("recon_"))
          .nest(&O::recon, reconstruct_param_table(), joint_recon_params(), "recon_",
                " (joint; splat.reconstruct's param of that name)");
  return table;
}

}  // namespace gslift
