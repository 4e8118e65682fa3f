#include "nodes/splat/reconstruct.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include <spdlog/spdlog.h>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/splat/density_strategy.hpp"
#include "nodes/splat/loss_terms.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/training_targets.hpp"

namespace gslift {
namespace {

// One Adam group per parameter array of the model, at 3DGS's rates.
class ModelOptimiser {
 public:
  ModelOptimiser(int sh_width, int feature_width, const ReconstructOptions& o)
      : means_(3, o.adam),
        log_scales_(3, o.adam),
        quats_(4, o.adam),
        opacity_(1, o.adam),
        sh_(sh_width, o.adam),
        features_(feature_width, o.adam),
        rates_(o.rates),
        iterations_(o.iterations),
        sh_lr_(sh_width, static_cast<float>(o.rates.sh_rest)) {
    std::fill_n(sh_lr_.begin(), 3, static_cast<float>(o.rates.sh_dc));
  }
  // One update; position rates decay log-linearly and scale with the scene extent (3DGS).
  void step(GaussianModel& model, const ModelGrads& grads, int step, double extent,
            const FeatureObjective* objective) {
    const LearningRates& lr = rates_;
    const size_t n = model.size();
    const float pos_lr = static_cast<float>(
        extent * exponential_lr(lr.position_init, lr.position_final, step, iterations_));
    means_.step(model.means.data(), grads.means.data(), n, pos_lr);
    log_scales_.step(model.log_scales.data(), grads.log_scales.data(), n,
                     static_cast<float>(lr.scale));
    quats_.step(model.quats.data(), grads.quats.data(), n, static_cast<float>(lr.rotation));
    opacity_.step(model.opacity_logits.data(), grads.opacity_logits.data(), n,
                  static_cast<float>(lr.opacity));
    sh_.step(model.sh.data(), grads.sh.data(), n, sh_lr_.data());
    if (objective)
      features_.step(model.features.data(), grads.features.data(), n,
                     static_cast<float>(objective->lr));
  }
  void remap(const std::vector<int>& source) {
    for (AdamGroup* g : {&means_, &log_scales_, &quats_, &opacity_, &sh_, &features_})
      g->remap(source);
  }

 private:
  AdamGroup means_, log_scales_, quats_, opacity_, sh_, features_;
  LearningRates rates_;
  int iterations_;
  std::vector<float> sh_lr_;
};

// Adds the wall seconds since the previous call (or construction) to the given phase.
class PhaseClock {
 public:
  void charge(double& phase) {
    const auto now = std::chrono::steady_clock::now();
    phase += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

// The depth priors that observe free space, at full resolution, seen from `poses` (per view of
// the capture, which the observations point into).
std::vector<DepthObservation> depth_observations(const std::vector<TrainTarget>& targets,
                                                 const Capture& capture,
                                                 const std::vector<Pose>& poses) {
  std::vector<DepthObservation> observations;
  for (const TrainTarget& t : targets)
    if (!t.full.depth.empty())
      observations.push_back(
          {&t.view->camera, &poses[t.view - capture.views.data()], t.full.depth});
  return observations;
}

// True when the mean loss of the last `window` steps improves on the window before by less than
// `tolerance` (relative), checked at the end of each window.
bool plateaued(const std::vector<double>& h, int window, double tolerance) {
  const int w = window;
  const int steps = static_cast<int>(h.size());
  if (w <= 0 || steps < 2 * w || steps % w != 0) return false;
  const double recent = std::accumulate(h.end() - w, h.end(), 0.0) / w;
  const double before = std::accumulate(h.end() - 2 * w, h.end() - w, 0.0) / w;
  return before - recent < tolerance * before;
}

// Each term's mean over the last 10% of the steps (at least one).
LossSummary tail_mean(const std::vector<LossSummary>& history) {
  LossSummary mean;
  if (history.empty()) return mean;
  mean.terms = history.front().terms;
  for (auto& term : mean.terms) term.second = 0;
  const size_t tail = std::max<size_t>(1, history.size() / 10);
  for (size_t i = history.size() - std::min(tail, history.size()); i < history.size(); ++i) {
    mean.total += history[i].total / tail;
    for (size_t k = 0; k < mean.terms.size(); ++k)
      mean.terms[k].second += history[i].terms[k].second / tail;
    mean.features += history[i].features / tail;
  }
  return mean;
}

cv::Mat rgb_image(std::vector<float>& data, int rows, int cols, int type) {
  return cv::Mat(rows, cols, type, data.data());
}

// PSNR (dB) of a float RGB render, clamped to [0,1], against a float target in [0,1], over the
// pixels of `mask` when one is given (NaN when it is empty of pixels).
double float_psnr(const cv::Mat& rendered, const cv::Mat& target, const cv::Mat1b& mask = {}) {
  cv::Mat clamped;
  cv::min(cv::max(rendered, 0.0), 1.0, clamped);
  const double pixels = mask.empty() ? clamped.total() : cv::countNonZero(mask);
  if (pixels == 0) return std::numeric_limits<double>::quiet_NaN();
  const double mse = cv::norm(clamped, target, cv::NORM_L2SQR, mask) / (pixels * 3);
  return mse > 0 ? 10 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

// One reconstruction's training state: the model, its targets, terms, optimiser and strategy.
class Training {
 public:
  Training(const Capture& capture, const ReconstructOptions& o, const FeatureObjective* objective,
           ReconstructResult& result);
  // One step: a view, its render, the terms' gradients, the update and density control.
  LossSummary step(int step);
  GaussianModel& model() { return model_; }
  // The strategy's counts into the result.
  void finish(ReconstructResult& result) const;
  const Eigen::Vector3f& background() const { return background_; }
  // Per view of the capture, its pose now (refined with refine_poses, else the written one).
  const std::vector<Pose>& poses() const { return poses_; }
  const std::vector<TrainTarget>& targets() const { return targets_; }

 private:
  // The step's render settings: background, SH degree, the channels the joining terms need.
  RenderSettings step_settings(int step, const TargetImages& target, int view_index);
  void evaluate_stage(TermStage stage, const StepRender& s, LossSummary& loss, RenderGrads& image);

  const Capture& capture_;
  const ReconstructOptions& o_;
  const FeatureObjective* objective_;
  ReconstructResult& result_;
  PhaseClock clock_;
  GaussianModel model_;
  double extent_ = 0;
  std::vector<TrainTarget> targets_;
  // Per view of the capture; the depth observations point into it, so it never resizes.
  std::vector<Pose> poses_;
  std::vector<PoseOptimiser> pose_optimisers_;
  int coarse_steps_ = 0;
  // The background of the records (and of training unless random).
  Eigen::Vector3f background_ = Eigen::Vector3f::Zero();
  std::vector<DepthObservation> observations_;
  LossTerms terms_;
  std::vector<bool> joins_;  // per term: whether it joins the current step
  ModelOptimiser adam_;
  std::optional<DensityStrategy> density_;
  ModelGrads grads_;
  RandomStream background_rng_, view_rng_;
  std::vector<int> order_;
};

GaussianModel initial_model(const Capture& capture, const ReconstructOptions& o,
                            const FeatureObjective* objective) {
  InitialiseOptions init = o.init;
  init.sh_degree = o.sh_degree;
  init.feature_dim = objective ? objective->dim : o.feature_dim;
  init.seed = o.seed;
  GaussianModel model = initialise_gaussians(capture, init);
  if (objective && objective->initialise) objective->initialise(model.size(), model.features);
  return model;
}

Training::Training(const Capture& capture, const ReconstructOptions& o,
                   const FeatureObjective* objective, ReconstructResult& result)
    : capture_(capture),
      o_(o),
      objective_(objective),
      result_(result),
      model_(initial_model(capture, o, objective)),
      adam_(GaussianModel::sh_coeffs(o.sh_degree) * 3, objective ? objective->dim : 0, o),
      background_rng_(stream_seed(o.seed, "reconstruct.background")),
      view_rng_(stream_seed(o.seed, "reconstruct.views")) {
  result.initial_gaussians = model_.size();
  extent_ = result.scene_extent = reconstruction_extent(capture, model_.means);
  coarse_steps_ = static_cast<int>(o.coarse_fraction * o.iterations);
  targets_ = make_targets(capture, capture.train_views(), o.normal_weight > 0, coarse_steps_ > 0);
  if (o.background == Background::White) background_ = Eigen::Vector3f::Ones();
  if (o.background == Background::Mean) background_ = mean_colour(targets_);
  for (const View& view : capture.views) poses_.push_back(view.pose);
  if (o.poses.refine)
    pose_optimisers_.assign(capture.views.size(),
                            PoseOptimiser(o.poses.rotation_lr, o.poses.translation_lr * extent_));
  observations_ = depth_observations(targets_, capture, poses_);
  terms_ = make_loss_terms(o, TermSetup{observations_});
  joins_.resize(terms_.size());
  for (const auto& term : terms_) result.phases.terms.emplace_back(term->name(), 0.0);
  density_.emplace(o, extent_, observations_);
  clock_.charge(result.phases.prepare);
}

RenderSettings Training::step_settings(int step, const TargetImages& target, int view_index) {
  RenderSettings settings;
  settings.background = background_;
  if (o_.background == Background::Random)
    for (int c = 0; c < 3; ++c)
      settings.background[c] = static_cast<float>(background_rng_.uniform());
  settings.sh_degree = std::min(o_.sh_degree, step / std::max(o_.sh_interval, 1));
  for (size_t k = 0; k < terms_.size(); ++k) {
    joins_[k] = terms_[k]->applies(step, o_.iterations, target);
    if (joins_[k]) terms_[k]->request(settings);
  }
  settings.features = objective_ != nullptr;
  if (objective_ && objective_->pixels) {
    auto pixels = std::make_shared<std::vector<uint32_t>>();
    objective_->pixels(step, view_index, target.camera.width, target.camera.height, *pixels);
    settings.feature_pixels = std::move(pixels);
  }
  return settings;
}

// Evaluates the terms of one stage that join the step, keeping their values in the terms' order.
void Training::evaluate_stage(TermStage stage, const StepRender& s, LossSummary& loss,
                              RenderGrads& image) {
  for (size_t k = 0; k < terms_.size(); ++k)
    if (joins_[k] && terms_[k]->stage() == stage) {
      const auto start = std::chrono::steady_clock::now();
      loss.terms[k].second = terms_[k]->evaluate(s, image, grads_);
      result_.phases.terms[k].second +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
}

LossSummary Training::step(int step) {
  // A fresh random permutation of the training views every epoch (3DGS's viewpoint stack).
  if (order_.empty()) {
    order_.resize(targets_.size());
    std::iota(order_.begin(), order_.end(), 0);
    view_rng_.shuffle(order_.begin(), order_.end());
  }
  const TrainTarget& train_target = targets_[order_.back()];
  order_.pop_back();
  const View& view = *train_target.view;
  const TargetImages& target = step < coarse_steps_ ? train_target.half : train_target.full;
  const int view_index = static_cast<int>(&view - capture_.views.data());
  const RenderSettings settings = step_settings(step, target, view_index);
  const Pose& pose = poses_[view_index];
  const RenderOutput out = render(model_, target.camera, pose, settings);
  PhaseSeconds& phases = result_.phases;
  clock_.charge(phases.render);

  // The terms by stage (loss_term.hpp): image gradients, the rasterizer's backward pass, then
  // the terms that add to the model's gradients. The total sums them in the terms' order.
  const StepRender s{model_, target.camera, pose, target, out};
  LossSummary loss;
  for (const auto& term : terms_) loss.terms.emplace_back(term->name(), 0.0);
  RenderGrads image;
  grads_.reset(model_);
  evaluate_stage(TermStage::Image, s, loss, image);
  if (objective_)
    loss.features = feature_objective_grads(*objective_, step, view_index, out, image);
  clock_.charge(phases.losses);
  PoseGradient pose_grad;
  render_backward(model_, target.camera, pose, settings, out, image, grads_,
                  o_.poses.refine ? &pose_grad : nullptr);
  clock_.charge(phases.backward);
  evaluate_stage(TermStage::Ray, s, loss, image);
  evaluate_stage(TermStage::Model, s, loss, image);
  for (size_t k = 0; k < terms_.size(); ++k)
    loss.total += terms_[k]->weight() * loss.terms[k].second;
  if (objective_) loss.total += objective_->weight * loss.features;
  // The render the step made, read as it is (the rasterizer's buffer is not written through).
  const cv::Mat rendered(out.height, out.width, CV_32FC3, const_cast<float*>(out.rgb.data()));
  loss.render_psnr = float_psnr(rendered, target.rgb);
  clock_.charge(phases.losses);

  adam_.step(model_, grads_, step, extent_, objective_);
  // The pose moves by the gradient of the render's terms (image stage), taken at this pose.
  if (o_.poses.refine) pose_optimisers_[view_index].step(poses_[view_index], pose_grad);
  if (objective_ && objective_->update) objective_->update(step);
  clock_.charge(phases.adam);
  if (auto change = density_->after_update(model_, grads_, step)) adam_.remap(change->source);
  clock_.charge(phases.density);
  return loss;
}

void Training::finish(ReconstructResult& result) const {
  result.free_space_pruned = density_->free_space_pruned();
  result.growth_refused = density_->growth_refused();
  result.emptied = density_->emptied();
}

// The mean PSNR of the model rendered at `views` against target(i), the float RGB image of
// views[i] in [0,1] (NaN without views): mean_psnr decodes each photo, the training PSNR takes
// the targets Training decoded (decoding every photo again took as long, after a DTU run, as
// decoding them for training had).
template <class Target>
double mean_render_psnr(const GaussianModel& model, const Capture& capture,
                        const std::vector<int>& views, const Eigen::Vector3f& background,
                        Target target) {
  if (views.empty()) return std::numeric_limits<double>::quiet_NaN();
  RenderSettings settings;
  settings.background = background;
  double sum = 0;
  for (size_t i = 0; i < views.size(); ++i) {
    const View& view = capture.views[views[i]];
    RenderOutput out = render(model, view.camera, view.pose, settings);
    sum += float_psnr(rgb_image(out.rgb, out.height, out.width, CV_32FC3), target(i));
  }
  return sum / static_cast<double>(views.size());
}

// The final model's PSNR over the training views (against their `targets`) and the held-out
// views, and with ground-truth depth the held-out geometry (rendered once for both).
void evaluate_model(const GaussianModel& model, const Capture& capture,
                    const std::vector<TrainTarget>& targets, const Eigen::Vector3f& background,
                    ReconstructResult& result) {
  // The targets are in capture.train_views() order, as Training keeps them.
  result.train_psnr = mean_render_psnr(model, capture, capture.train_views(), background,
                                       [&](size_t i) { return targets[i].full.rgb; });
  const std::vector<int> test = capture.test_views();
  const bool gt_depth = std::all_of(capture.views.begin(), capture.views.end(),
                                    [](const View& v) { return v.gt_depth.present(); });
  if (!test.empty() && gt_depth) {
    result.test_geometry = mean_view_geometry(model, capture, test, capture.train_views(),
                                              background, &result.test_pictures);
    result.test_psnr = result.test_geometry->psnr;
  } else {
    result.test_psnr = mean_psnr(model, capture, test, background);
  }
}

// Each held-out view's pose registered to its photo with the model fixed (pose_correction.hpp).
void refine_held_out_poses(const GaussianModel& model, const Capture& capture,
                           const PoseRefinementOptions& o, const Eigen::Vector3f& background,
                           double extent, std::vector<Pose>& poses) {
  if (!o.refine) return;
  for (int v : capture.test_views()) {
    const View& view = capture.views[v];
    poses[v] = refine_pose_to_photo(model, view.camera, poses[v], load_view_rgb(view), background,
                                    o.held_out_steps, o.rotation_lr, o.translation_lr * extent,
                                    int(std::lround(o.held_out_coarse * o.held_out_steps)));
  }
}

// The depth-prior levers (the depth_prior recipe's) do nothing on a capture whose training views
// have no depth prior: a run on plain photos says so instead of implying that they ran. Returns
// the number of training views with a depth prior.
size_t warn_inert_depth_levers(const Capture& capture, const ReconstructOptions& o) {
  size_t with_depth = 0;
  for (int v : capture.train_views()) with_depth += capture.views[v].depth.present();
  std::string inert;
  const std::pair<bool, const char*> levers[] = {
      {o.line_of_sight_weight > 0, "line_of_sight_weight"},
      {o.edge_extent_weight > 0, "edge_extent_weight"},
      {o.floaters.active(), "prune_line_of_sight / prune_behind / prune_hidden"}};
  for (const auto& [on, name] : levers)
    if (on) inert += (inert.empty() ? "" : ", ") + std::string(name);
  if (with_depth == 0 && !inert.empty())
    spdlog::warn(
        "reconstruction of capture '{}': no training view has a depth prior, so {} do nothing "
        "here (the depth_prior recipe adds only its mean-colour background)",
        capture.name, inert);
  return with_depth;
}

}  // namespace

double LossSummary::term(const std::string& name) const {
  for (const auto& [n, value] : terms)
    if (n == name) return value;
  return 0;
}

double psnr(const cv::Mat& rendered, const cv::Mat& target_rgb8, const cv::Mat1b& mask) {
  cv::Mat target;
  target_rgb8.convertTo(target, CV_32FC3, 1.0 / 255);
  return float_psnr(rendered, target, mask);
}

double mean_psnr(const GaussianModel& model, const Capture& capture, const std::vector<int>& views,
                 const Eigen::Vector3f& background) {
  return mean_render_psnr(model, capture, views, background, [&](size_t i) {
    cv::Mat target;
    load_view_rgb(capture.views[views[i]]).convertTo(target, CV_32FC3, 1.0 / 255);
    return target;
  });
}

const char* model_size_reason(const ReconstructResult& result) {
  if (result.growth_refused > 0) return "budget";
  return result.stopped_early ? "plateau" : "iterations";
}

ReconstructResult reconstruct(const Capture& capture, const ReconstructOptions& options,
                              const ReconstructCallback& callback,
                              const FeatureObjective* objective) {
  reconstruct_param_table().validate(options, "splat.reconstruct");
  reconstruct_tuning_table().validate(options, "splat.reconstruct");
  const auto start = std::chrono::steady_clock::now();
  if (capture.train_views().empty())
    throw InputError("capture '" + capture.name + "' has no training view");
  ReconstructResult result;
  result.depth_prior_views = warn_inert_depth_levers(capture, options);
  Training training(capture, options, objective, result);
  std::vector<LossSummary> history;
  for (int step = 0; step < options.iterations; ++step) {
    history.push_back(training.step(step));
    result.loss_history.push_back(history.back().total);
    result.iterations_run = step + 1;
    if (callback)
      callback({step + 1, options.iterations, history.back().total, history.back().render_psnr},
               training.model().size());
    if (plateaued(result.loss_history, options.plateau_window, options.plateau_tolerance)) {
      result.stopped_early = true;
      break;
    }
  }
  training.finish(result);
  result.final_loss = tail_mean(history);
  result.poses = training.poses();
  const auto registration = std::chrono::steady_clock::now();
  refine_held_out_poses(training.model(), capture, options.poses, training.background(),
                        result.scene_extent, result.poses);
  result.phases.held_out_poses =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - registration).count();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The records see the views where the poses put them.
  Capture posed = capture;
  for (size_t v = 0; v < posed.views.size(); ++v) posed.views[v].pose = result.poses[v];
  evaluate_model(training.model(), posed, training.targets(), training.background(), result);
  result.model = std::move(training.model());
  return result;
}

}  // namespace gslift
