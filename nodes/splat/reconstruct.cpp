#include "nodes/splat/reconstruct.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/splat/depth_distortion_loss.hpp"
#include "nodes/splat/depth_normals.hpp"
#include "nodes/splat/line_of_sight_loss.hpp"
#include "nodes/splat/losses.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {
namespace {

// What one training view contributes, decoded once.
// A training view's targets at one resolution, decoded once.
struct TargetImages {
  Camera camera;                   // the view's camera at this resolution
  cv::Mat rgb;                     // CV_32FC3 [0,1]
  std::optional<SsimTarget> ssim;  // rgb's windowed statistics
  cv::Mat depth;                   // CV_32FC1 metres, empty without a prior
  cv::Mat normals;                 // CV_32FC3 world-space, empty without a prior
};

// What one training view contributes: full-resolution targets and, for coarse-to-fine, a copy at
// half resolution (empty camera when unused).
struct TrainTarget {
  const View* view = nullptr;
  TargetImages full, half;
};

cv::Mat load_rgb(const View& view) {
  const cv::Mat rgb = view.rgb.load();
  if (rgb.type() != CV_8UC3 || rgb.cols != view.camera.width || rgb.rows != view.camera.height)
    throw InputError("view '" + view.name +
                     "': RGB image must be 8-bit 3-channel of the camera size " +
                     std::to_string(view.camera.width) + "x" + std::to_string(view.camera.height));
  return rgb;
}

TargetImages make_images(const View& view, const Camera& camera, const cv::Mat& rgb,
                         const cv::Mat& depth, bool need_normals) {
  TargetImages t;
  t.camera = camera;
  t.rgb = rgb;
  t.ssim.emplace(t.rgb);
  t.depth = depth;
  if (!depth.empty() && need_normals)
    t.normals = normals_from_depth(depth, camera, view.pose, 0.1, 1, kPriorNormalSmoothing);
  return t;
}

TrainTarget make_target(const View& view, bool need_normals, bool need_half) {
  TrainTarget t;
  t.view = &view;
  cv::Mat rgb, depth;
  load_rgb(view).convertTo(rgb, CV_32FC3, 1.0 / 255);
  if (view.depth.present()) {
    depth = view.depth.load();
    if (depth.type() != CV_32FC1 || depth.size() != rgb.size())
      throw InputError("view '" + view.name + "': depth prior must be CV_32F of the image size");
  }
  t.full = make_images(view, view.camera, rgb, depth, need_normals);
  if (need_half) {
    const Camera half = view.camera.scaled(0.5);
    const cv::Size size(half.width, half.height);
    cv::Mat small_rgb, small_depth;
    cv::resize(rgb, small_rgb, size, 0, 0, cv::INTER_AREA);
    // Nearest, not area: averaging would blend invalid (0) pixels and depth edges into depths
    // that exist nowhere.
    if (!depth.empty()) cv::resize(depth, small_depth, size, 0, 0, cv::INTER_NEAREST);
    t.half = make_images(view, half, small_rgb, small_depth, need_normals);
  }
  return t;
}

// One Adam group per parameter array of the model.
struct ModelOptimiser {
  AdamGroup means, log_scales, quats, opacity, sh, features;
  ModelOptimiser(int sh_width, int feature_width, const AdamSettings& s)
      : means(3, s),
        log_scales(3, s),
        quats(4, s),
        opacity(1, s),
        sh(sh_width, s),
        features(feature_width, s) {}
  void remap(const std::vector<int>& source) {
    for (AdamGroup* g : {&means, &log_scales, &quats, &opacity, &sh, &features}) g->remap(source);
  }
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

cv::Mat wrap(std::vector<float>& data, int rows, int cols, int type) {
  return cv::Mat(rows, cols, type, data.data());
}

// The image's values times `weight`, as the flat vector RenderGrads takes (one pass, no temporary).
std::vector<float> scaled_vector(const cv::Mat& m, double weight) {
  const cv::Mat c = m.isContinuous() ? m : m.clone();
  const float* p = c.ptr<float>();
  std::vector<float> out(c.total() * c.channels());
  const float w = static_cast<float>(weight);
  for (size_t i = 0; i < out.size(); ++i) out[i] = w * p[i];
  return out;
}

// The mean colour of the training images (full resolution).
Eigen::Vector3f mean_colour(const std::vector<TrainTarget>& targets) {
  cv::Scalar sum;
  for (const TrainTarget& t : targets) sum += cv::mean(t.full.rgb);
  const double n = static_cast<double>(targets.size());
  return Eigen::Vector3f(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
}

}  // namespace

const EnumNames<Background>& background_names() {
  static const EnumNames<Background> names = {{Background::Black, "black"},
                                              {Background::White, "white"},
                                              {Background::Random, "random"},
                                              {Background::Mean, "mean"}};
  return names;
}

double psnr(const cv::Mat& rendered, const cv::Mat& target_rgb8, const cv::Mat1b& mask) {
  cv::Mat clamped, target;
  cv::min(cv::max(rendered, 0.0), 1.0, clamped);
  target_rgb8.convertTo(target, CV_32FC3, 1.0 / 255);
  const double pixels = mask.empty() ? clamped.total() : cv::countNonZero(mask);
  if (pixels == 0) return std::numeric_limits<double>::quiet_NaN();
  const double mse = cv::norm(clamped, target, cv::NORM_L2SQR, mask) / (pixels * 3);
  return mse > 0 ? 10 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

double mean_psnr(const GaussianModel& model, const Capture& capture, const std::vector<int>& views,
                 const Eigen::Vector3f& background) {
  if (views.empty()) return std::numeric_limits<double>::quiet_NaN();
  RenderSettings settings;
  settings.background = background;
  double sum = 0;
  for (int v : views) {
    const View& view = capture.views[v];
    RenderOutput out = render(model, view.camera, view.pose, settings);
    sum += psnr(wrap(out.rgb, out.height, out.width, CV_32FC3), load_rgb(view));
  }
  return sum / static_cast<double>(views.size());
}

const char* model_size_reason(const ReconstructResult& result) {
  if (result.growth_refused > 0) return "budget";
  return result.stopped_early ? "plateau" : "iterations";
}

ReconstructResult reconstruct(const Capture& capture, const ReconstructOptions& options,
                              const ReconstructCallback& callback,
                              const FeatureObjective* objective) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<int> train = capture.train_views();
  if (train.empty()) throw InputError("capture '" + capture.name + "' has no training view");

  ReconstructResult result;
  PhaseClock clock;
  PhaseSeconds& phases = result.phases;
  // The background of the records (and of training unless random).
  Eigen::Vector3f background = Eigen::Vector3f::Zero();
  InitialiseOptions init = options.init;
  init.sh_degree = options.sh_degree;
  init.feature_dim = objective ? objective->dim : options.feature_dim;
  init.seed = options.seed;
  GaussianModel model = initialise_gaussians(capture, init);
  if (objective && objective->initialise) objective->initialise(model.size(), model.features);
  result.initial_gaussians = model.size();
  const double extent = reconstruction_extent(capture, model.means);
  result.scene_extent = extent;

  std::vector<TrainTarget> targets;
  const int coarse_steps = static_cast<int>(options.coarse_fraction * options.iterations);
  for (int v : train)
    targets.push_back(make_target(capture.views[v], options.normal_weight > 0, coarse_steps > 0));

  if (options.background == Background::White) background = Eigen::Vector3f::Ones();
  if (options.background == Background::Mean) background = mean_colour(targets);

  const int K = GaussianModel::sh_coeffs(options.sh_degree);
  ModelOptimiser adam(K * 3, objective ? objective->dim : 0, options.adam);
  const LearningRates& lr = options.rates;
  std::vector<float> sh_lr(K * 3, static_cast<float>(lr.sh_rest));
  std::fill_n(sh_lr.begin(), 3, static_cast<float>(lr.sh_dc));

  // The depth priors that observe free space, at full resolution.
  std::vector<DepthObservation> observations;
  for (const TrainTarget& t : targets)
    if (!t.full.depth.empty())
      observations.push_back({&t.view->camera, &t.view->pose, t.full.depth});
  // Where the depth priors jump (the training views' silhouettes), for the edge-extent term.
  std::vector<cv::Mat1b> depth_edges;
  if (options.edge_extent_weight > 0)
    depth_edges = depth_edge_masks(observations, 0.1, kDiscontinuityRadius);

  // Pseudo-views between the training cameras, warped from their images through the depth prior.
  std::vector<PseudoView> pseudo;
  if (options.pseudo_weight > 0) {
    std::vector<WarpSource> sources;
    for (const TrainTarget& t : targets)
      if (!t.full.depth.empty())
        sources.push_back({&t.view->camera, &t.view->pose, t.full.rgb, t.full.depth});
    pseudo = pseudo_views_between(sources, options.pseudo_max_angle, 0.5);
  }
  result.pseudo_views = pseudo.size();

  DensityStats stats;
  FreeSpacePruner pruner(options.floaters);
  ModelGrads grads;
  std::vector<float> flatness_grad, opacity_grad, anisotropy_grad, edge_grad;
  RandomStream background_rng(stream_seed(options.seed, "reconstruct.background"));
  std::vector<int> order;
  RandomStream view_rng(stream_seed(options.seed, "reconstruct.views"));
  std::vector<LossSummary> history;
  clock.charge(phases.prepare);

  for (int step = 0; step < options.iterations; ++step) {
    // A fresh random permutation of the training views every epoch (3DGS's viewpoint stack).
    if (order.empty()) {
      order.resize(targets.size());
      std::iota(order.begin(), order.end(), 0);
      view_rng.shuffle(order.begin(), order.end());
    }
    const TrainTarget& train_target = targets[order.back()];
    order.pop_back();
    const View& view = *train_target.view;
    const TargetImages& target = step < coarse_steps ? train_target.half : train_target.full;

    RenderSettings settings;
    settings.background = background;
    if (options.background == Background::Random)
      for (int c = 0; c < 3; ++c)
        settings.background[c] = static_cast<float>(background_rng.uniform());
    settings.sh_degree = std::min(options.sh_degree, step / std::max(options.sh_interval, 1));
    const bool use_depth = options.depth_weight > 0 && !target.depth.empty();
    const bool use_normal = options.normal_weight > 0 && !target.normals.empty();
    settings.depth = use_depth;
    settings.normal = use_normal;
    settings.features = objective != nullptr;
    const int view_index = static_cast<int>(&view - capture.views.data());
    if (objective && objective->pixels) {
      auto pixels = std::make_shared<std::vector<uint32_t>>();
      objective->pixels(step, view_index, target.camera.width, target.camera.height, *pixels);
      settings.feature_pixels = std::move(pixels);
    }
    RenderOutput out = render(model, target.camera, view.pose, settings);
    const int H = out.height, W = out.width;
    clock.charge(phases.render);

    LossSummary loss;
    RenderGrads rgrads;
    cv::Mat grad;
    loss.photometric =
        photometric_loss(wrap(out.rgb, H, W, CV_32FC3), *target.ssim, options.ssim_lambda, &grad)
            .value;
    rgrads.rgb = scaled_vector(grad, 1.0);
    if (use_depth) {
      loss.depth = depth_log_l1_loss(wrap(out.depth, H, W, CV_32FC1), target.depth, &grad);
      rgrads.depth = scaled_vector(grad, options.depth_weight);
    }
    if (use_normal) {
      loss.normal = normal_cosine_loss(wrap(out.normal, H, W, CV_32FC3), target.normals, &grad);
      rgrads.normal = scaled_vector(grad, options.normal_weight);
    }
    if (objective)
      loss.features = feature_objective_grads(*objective, step, view_index, out, rgrads);
    clock.charge(phases.losses);
    grads.reset(model);
    render_backward(model, target.camera, view.pose, settings, out, rgrads, grads);
    const bool line_of_sight_step =
        (options.line_of_sight_weight > 0 || options.surface_opacity_weight > 0) &&
        step >= options.line_of_sight_start * options.iterations &&
        step % std::max(options.line_of_sight_every, 1) == 0;
    // Adds the line-of-sight and surface-opacity losses of a render against its depth prior to the
    // step's loss and grads.
    const auto line_of_sight = [&](const Camera& camera, const Pose& pose, const cv::Mat1f& depth,
                                   const RenderOutput& forward) {
      clock.charge(phases.backward);
      if (options.line_of_sight_weight > 0)
        loss.line_of_sight +=
            line_of_sight_loss(model, camera, pose, depth, forward, options.floaters.tolerance,
                               options.line_of_sight_weight, &grads, options.floaters.ray_depth);
      if (options.surface_opacity_weight > 0)
        loss.surface_opacity += surface_opacity_loss(
            model, camera, pose, depth, forward, options.floaters.tolerance,
            options.surface_opacity_weight, &grads, options.floaters.ray_depth);
      clock.charge(phases.losses);
    };
    if (line_of_sight_step && !target.depth.empty())
      line_of_sight(target.camera, view.pose, target.depth, out);
    if (options.distortion_weight > 0 && step >= options.distortion_start * options.iterations) {
      clock.charge(phases.backward);
      loss.distortion = depth_distortion_loss(model, target.camera, view.pose, out,
                                              options.distortion_weight, &grads);
      clock.charge(phases.losses);
    }
    if (!pseudo.empty() && step >= options.pseudo_start * options.iterations &&
        step % std::max(options.pseudo_every, 1) == 0) {
      const PseudoView& p = pseudo[(step / std::max(options.pseudo_every, 1)) % pseudo.size()];
      RenderSettings ps = settings;
      ps.depth = options.depth_weight > 0;
      ps.normal = false;
      ps.features = false;
      RenderOutput po = render(model, p.camera, p.pose, ps);
      clock.charge(phases.render);
      RenderGrads pg;
      loss.pseudo =
          masked_l1_loss(wrap(po.rgb, po.height, po.width, CV_32FC3), p.rgb, p.valid, &grad);
      pg.rgb = scaled_vector(grad, options.pseudo_weight);
      if (ps.depth) {
        loss.pseudo +=
            options.depth_weight *
            depth_log_l1_loss(wrap(po.depth, po.height, po.width, CV_32FC1), p.depth, &grad);
        pg.depth = scaled_vector(grad, options.pseudo_weight * options.depth_weight);
      }
      clock.charge(phases.losses);
      render_backward(model, p.camera, p.pose, ps, po, pg, grads);
      if (line_of_sight_step) line_of_sight(p.camera, p.pose, p.depth, po);
    }
    clock.charge(phases.backward);
    if (options.scale_weight > 0) {
      loss.flatness = flatness_loss(model.log_scales, &flatness_grad);
      for (size_t i = 0; i < flatness_grad.size(); ++i)
        grads.log_scales[i] += static_cast<float>(options.scale_weight * flatness_grad[i]);
    }
    if (options.anisotropy_weight > 0) {
      loss.anisotropy =
          anisotropy_loss(model.log_scales, options.anisotropy_ratio, &anisotropy_grad);
      for (size_t i = 0; i < anisotropy_grad.size(); ++i)
        grads.log_scales[i] += static_cast<float>(options.anisotropy_weight * anisotropy_grad[i]);
    }
    if (options.edge_extent_weight > 0) {
      loss.edge_extent = depth_edge_extent_loss(model, observations, depth_edges,
                                                options.floaters.tolerance, &edge_grad);
      for (size_t i = 0; i < edge_grad.size(); ++i)
        grads.log_scales[i] += static_cast<float>(options.edge_extent_weight * edge_grad[i]);
    }
    if (options.opacity_entropy_weight > 0) {
      loss.opacity_entropy = opacity_entropy_loss(model.opacity_logits, &opacity_grad);
      for (size_t i = 0; i < opacity_grad.size(); ++i)
        grads.opacity_logits[i] +=
            static_cast<float>(options.opacity_entropy_weight * opacity_grad[i]);
    }
    loss.total = loss.photometric + options.depth_weight * loss.depth +
                 options.normal_weight * loss.normal + options.scale_weight * loss.flatness +
                 options.opacity_entropy_weight * loss.opacity_entropy +
                 options.anisotropy_weight * loss.anisotropy +
                 options.edge_extent_weight * loss.edge_extent +
                 options.line_of_sight_weight * loss.line_of_sight +
                 options.surface_opacity_weight * loss.surface_opacity +
                 options.distortion_weight * loss.distortion + options.pseudo_weight * loss.pseudo;
    if (objective) loss.total += objective->weight * loss.features;
    clock.charge(phases.losses);
    history.push_back(loss);
    result.loss_history.push_back(loss.total);

    const size_t n = model.size();
    const float pos_lr = static_cast<float>(
        extent * exponential_lr(lr.position_init, lr.position_final, step, options.iterations));
    adam.means.step(model.means.data(), grads.means.data(), n, pos_lr);
    adam.log_scales.step(model.log_scales.data(), grads.log_scales.data(), n,
                         static_cast<float>(lr.scale));
    adam.quats.step(model.quats.data(), grads.quats.data(), n, static_cast<float>(lr.rotation));
    adam.opacity.step(model.opacity_logits.data(), grads.opacity_logits.data(), n,
                      static_cast<float>(lr.opacity));
    adam.sh.step(model.sh.data(), grads.sh.data(), n, sh_lr.data());
    if (objective) {
      adam.features.step(model.features.data(), grads.features.data(), n,
                         static_cast<float>(objective->lr));
      if (objective->update) objective->update(step);
    }
    clock.charge(phases.adam);

    if (options.densify) {
      stats.add(grads.mean2d_abs, grads.visible);
      const DensityControlOptions& d = options.density;
      const bool density_step = is_density_step(d, step, options.iterations);
      // Free-space pruning keeps its rounds after growth stops (floaters can drift in late).
      const bool floater_step = options.floaters.active() && !observations.empty() &&
                                d.interval > 0 && step >= d.start &&
                                (step - d.start) % d.interval == 0;
      if (density_step || floater_step) {
        std::vector<char> floaters;
        if (floater_step) floaters = pruner.prune_mask(model, observations);
        result.free_space_pruned += std::count(floaters.begin(), floaters.end(), 1);
        // Outside density rounds no statistics are passed: pruning only, no growth.
        const DensityChange change = densify_and_prune(model, density_step ? stats : DensityStats{},
                                                       d, extent, options.seed + step, floaters);
        result.growth_refused += change.refused;
        if (model.size() == 0 && !result.emptied)
          result.emptied = ReconstructResult::Emptied{step, change.pruned_opacity,
                                                      change.pruned_scale, change.pruned_marked};
        adam.remap(change.source);
        pruner.remap(change.source);
        if (density_step)
          stats.clear();
        else
          stats.remap(change.source);
      }
      clock.charge(phases.density);
    }
    const DensityControlOptions& d = options.density;
    if (options.extent_clamp.active() && d.interval > 0 && step >= d.start &&
        (step - d.start) % d.interval == 0) {
      result.extent_clamped +=
          clamp_extent_to_free_space(model, observations, options.extent_clamp);
      clock.charge(phases.density);
    }
    result.iterations_run = step + 1;
    if (callback) callback(step, options.iterations, loss.total, model.size());

    const int w = options.plateau_window;
    if (w > 0 && step + 1 >= 2 * w && (step + 1) % w == 0) {
      const auto& h = result.loss_history;
      const double recent = std::accumulate(h.end() - w, h.end(), 0.0) / w;
      const double before = std::accumulate(h.end() - 2 * w, h.end() - w, 0.0) / w;
      if (before - recent < options.plateau_tolerance * before) {
        result.stopped_early = true;
        break;
      }
    }
  }

  const size_t tail = std::max<size_t>(1, history.size() / 10);
  for (size_t i = history.size() - std::min(tail, history.size()); i < history.size(); ++i) {
    result.final_loss.total += history[i].total / tail;
    result.final_loss.photometric += history[i].photometric / tail;
    result.final_loss.depth += history[i].depth / tail;
    result.final_loss.normal += history[i].normal / tail;
    result.final_loss.flatness += history[i].flatness / tail;
    result.final_loss.opacity_entropy += history[i].opacity_entropy / tail;
    result.final_loss.anisotropy += history[i].anisotropy / tail;
    result.final_loss.edge_extent += history[i].edge_extent / tail;
    result.final_loss.line_of_sight += history[i].line_of_sight / tail;
    result.final_loss.surface_opacity += history[i].surface_opacity / tail;
    result.final_loss.distortion += history[i].distortion / tail;
    result.final_loss.pseudo += history[i].pseudo / tail;
    result.final_loss.features += history[i].features / tail;
  }
  result.extent_clamped += clamp_extent_to_free_space(model, observations, options.extent_clamp);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.train_psnr = mean_psnr(model, capture, train, background);
  const std::vector<int> test = capture.test_views();
  const bool gt_depth = std::all_of(capture.views.begin(), capture.views.end(),
                                    [](const View& v) { return v.gt_depth.present(); });
  // With ground-truth depth the held-out views are rendered once, for their PSNR and geometry.
  if (!test.empty() && gt_depth) {
    result.test_geometry =
        mean_view_geometry(model, capture, test, train, background, &result.test_pictures);
    result.test_psnr = result.test_geometry->psnr;
  } else {
    result.test_psnr = mean_psnr(model, capture, test, background);
  }
  result.model = std::move(model);
  return result;
}

const ParamTable<ReconstructOptions>& reconstruct_param_table() {
  using O = ReconstructOptions;
  using D = DensityControlOptions;
  using I = InitialiseOptions;
  using F = FreeSpacePruneOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("iterations", &O::iterations, "optimisation steps (LangOR: 500)", 1, 1e6)
          .add("sh_degree", &O::sh_degree, "highest SH degree, raised one every 100 steps", 0, 3)
          .add("ssim_lambda", &O::ssim_lambda, "weight of D-SSIM in the photometric loss", 0, 1)
          .add("depth_weight", &O::depth_weight,
               "depth log-L1 against the depth prior (DN-Splatter 0.2); 0 = off", 0)
          .add("normal_weight", &O::normal_weight,
               "1 - cos between rendered normals and depth-prior normals; 0 = off", 0)
          .add("scale_weight", &O::scale_weight,
               "flatness regulariser, mean smallest scale in metres; 0 = off", 0)
          .add("background", &O::background, background_names(),
               "rendered behind the model in training and records: black, white (NeRF-synthetic "
               "captures), random (a new colour each step, records over black), mean (the "
               "training images' mean colour, the best guess for what no view saw)")
          .add("opacity_entropy_weight", &O::opacity_entropy_weight,
               "binary entropy of the opacities, pushing each towards 0 or 1; 0 = off", 0)
          .add("anisotropy_weight", &O::anisotropy_weight,
               "penalty on a largest / second-largest scale ratio above anisotropy_ratio "
               "(needles and elongated discs); 0 = off",
               0)
          .add("anisotropy_ratio", &O::anisotropy_ratio,
               "the scale ratio the anisotropy penalty starts at", 1)
          .add("edge_extent_weight", &O::edge_extent_weight,
               "penalty on the extent along a training view's ray of Gaussians on the near side "
               "of its depth prior's discontinuities (silhouette overhangs); 0 = off",
               0)
          .add("line_of_sight_weight", &O::line_of_sight_weight,
               "weight of the opacity training pixels accumulate in front of their depth prior "
               "(by free_space_tolerance); 0 = off",
               0)
          .add("line_of_sight_every", &O::line_of_sight_every,
               "the line-of-sight loss joins every this many steps", 1)
          .add("line_of_sight_start", &O::line_of_sight_start,
               "fraction of the steps before the line-of-sight loss joins", 0, 1)
          .add("surface_opacity_weight", &O::surface_opacity_weight,
               "weight of the transmittance left past each training pixel's depth prior, on "
               "the line-of-sight loss's steps; 0 = off",
               0)
          .add("distortion_weight", &O::distortion_weight,
               "weight of the depth distortion: the spread in log depth of each training pixel's "
               "blending weights; 0 = off",
               0)
          .add("distortion_start", &O::distortion_start,
               "fraction of the steps before the depth distortion joins", 0, 1)
          .add("coarse_fraction", &O::coarse_fraction,
               "fraction of the steps trained at half resolution first; 0 = off", 0, 1)
          .add("densify", &O::densify, "clone/split/prune on the compressed schedule")
          .add("pseudo_weight", &O::pseudo_weight,
               "weight of the depth-warped pseudo-views between training cameras; 0 = off", 0)
          .add("pseudo_every", &O::pseudo_every, "a pseudo-view joins every this many steps", 1,
               1000)
          .add("pseudo_start", &O::pseudo_start,
               "fraction of the steps before the pseudo-views join", 0, 1)
          .nest(&O::density,
                ParamTable<D>()
                    .add("max_gaussians", &D::max_gaussians, "Gaussian budget for densification", 1)
                    .add("prune_opacity", &D::prune_opacity,
                         "densification rounds prune Gaussians below this opacity", 0, 1))
          .nest(&O::floaters,
                ParamTable<F>()
                    .add("prune_free_space_views", &F::free_space_views,
                         "densification rounds prune Gaussians whose centre this many training "
                         "depth priors see as empty space; 0 = off",
                         0, 255)
                    .add("prune_min_seen_views", &F::min_seen_views,
                         "densification rounds prune Gaussians that fewer training views see; 0 "
                         "= off",
                         0, 255)
                    .add("prune_line_of_sight", &F::line_of_sight,
                         "densification rounds prune Gaussians that draw more than this fraction "
                         "of their training-view weight in front of the depth prior; 0 = off",
                         0, 1)
                    .add("prune_behind", &F::behind,
                         "densification rounds prune Gaussians that draw more than this fraction "
                         "of their training-view weight behind the depth prior; 0 = off",
                         0, 1)
                    .add("prune_hidden", &F::hidden,
                         "densification rounds prune Gaussians more than this fraction of whose "
                         "footprint in the training views lies behind the depth prior; 0 = off",
                         0, 1)
                    .add("line_of_sight_rounds", &F::line_of_sight_rounds,
                         "prune_line_of_sight prunes only Gaussians that violate it in this many "
                         "pruning rounds running",
                         1, 255)
                    .add("free_space_ray_depth", &F::ray_depth,
                         "the free-space weight and footprint tests and the line-of-sight loss "
                         "place each Gaussian at its density maximum along each pixel's ray, not "
                         "at its centre's depth")
                    .add("free_space_tolerance", &F::tolerance,
                         "relative depth margin of the free-space, seen and line-of-sight tests", 0,
                         1))
          .nest(&O::extent_clamp,
                ParamTable<ExtentClampOptions>()
                    .add("extent_clamp_sigmas", &ExtentClampOptions::sigmas,
                         "shrink each Gaussian axis until the points this many standard "
                         "deviations along it leave the training depth priors' free space "
                         "(silhouette rims); 0 = off",
                         0, 10)
                    .add("extent_clamp_tolerance", &ExtentClampOptions::tolerance,
                         "relative depth margin of the extent clamp's free-space test", 0, 1))
          .add("feature_dim", &O::feature_dim,
               "feature channels allocated (zero) for later stages, not trained here", 0, 512)
          .nest(&O::init,
                ParamTable<I>()
                    .add("init", &I::source, init_source_names(),
                         "initial points: depth prior, sparse points, random points in the "
                         "volume the training views share, or auto (depth when every training "
                         "view has one, else points when the capture has them, else random)")
                    .add("footprint_factor", &I::footprint_factor,
                         "initial voxel = this x the median pixel footprint (larger = fewer "
                         "Gaussians)",
                         0.1, 100)
                    .add("normal_thickness", &I::normal_thickness,
                         "initial scale along the depth prior's normal / in-plane scale (1 = "
                         "isotropic)",
                         0.01, 1)
                    .add("init_scale_factor", &I::scale_factor,
                         "initial scale = this x the distance to the 3 nearest initial points",
                         1e-3, 100)
                    .add("init_scale_distance", &I::scale_distance, neighbour_distance_names(),
                         "that distance: rms (3DGS) or mean (OpenSplat) of the 3 nearest")
                    .add("random_points", &I::random_points,
                         "init random: points drawn in the volume the training views share", 1, 1e7)
                    .add("random_min_views", &I::random_min_views,
                         "init random: fraction of the training views (at least 2) that must see "
                         "a point",
                         0, 1))
          .add("plateau_window", &O::plateau_window,
               "early stop when a window of this many steps improves the mean loss by less than "
               "plateau_tolerance; 0 = off",
               0)
          .add("plateau_tolerance", &O::plateau_tolerance,
               "relative improvement per window below which the run stops", 0, 1);
  return table;
}

}  // namespace gslift
