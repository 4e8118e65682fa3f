// Geometry-constrained 3DGS reconstruction (3DGS, Kerbl et al. 2023, and LangOR §2.3): initialise
// from the depth prior or points, then optimise a list of loss terms (loss_terms.hpp: photometric,
// depth, normal, flatness and the depth prior's line-of-sight and edge-extent terms) over the
// training views with Adam, with density control and pruning (density_strategy.hpp) rescheduled
// for short runs.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "base/training_step.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/adam.hpp"
#include "nodes/splat/density_control.hpp"
#include "nodes/splat/depth_edge_extent.hpp"
#include "nodes/splat/feature_objective.hpp"
#include "nodes/splat/free_space.hpp"
#include "nodes/splat/initialise.hpp"
#include "nodes/splat/pose_correction.hpp"
#include "nodes/splat/view_geometry.hpp"
#include "param/param_table.hpp"

namespace gslift {

// 3DGS learning rates (the 3DGS reference code). Position rates are multiplied by the scene extent.
struct LearningRates {
  double position_init = 1.6e-4;
  double position_final = 1.6e-6;  // reached at the last iteration, log-linear decay
  // [decision] Colour and opacity at twice the newer 3DGS code's rates (sh_dc 2.5e-3, opacity
  // 0.025; opacity 0.05 is the paper release's): 500 steps are 1/60 of 3DGS's run. On the embedded
  // OR (coarse-to-fine, footprint 12) train PSNR 29.99 -> 30.43 dB, 78 -> 72 s CPU
  // (bench/results/splat_recon_sweep.json).
  double sh_dc = 5e-3;
  double sh_rest = 2.5e-3 / 20;  // 1.25e-4
  double opacity = 0.05;
  double scale = 5e-3;
  double rotation = 1e-3;
};

enum class Background { Black, White, Random, Mean };
const EnumNames<Background>& background_names();  // black, white, random, mean

struct ReconstructOptions {
  int iterations = 500;  // LangOR: 500
  // Highest SH degree; training starts at 0 and adds one degree every sh_interval steps (3DGS
  // does so every 1000 of 30000 steps; compressed here).
  int sh_degree = 1;
  int sh_interval = 100;
  // Feature channels allocated (zero) for later stages; not trained here. With a FeatureObjective
  // the objective's dim is used instead and the features train with the geometry.
  int feature_dim = 0;
  double ssim_lambda = 0.2;  // photometric (1 - lambda) L1 + lambda D-SSIM
  // What the model is rendered over, in training and in the PSNR records.
  //  black: 3DGS's default.
  //  white: 3DGS's --white_background, for NeRF-synthetic captures, whose RGBA images ingest
  //    composites onto white: over black the model must build a white shell around the object,
  //    which a held-out view then sees as haze.
  //  random: a new uniformly random colour every training step, so that a half-transparent model
  //    can never blend towards a known background for free; records over black.
  //  mean: the mean colour of the training images. A held-out view shows surfaces no training
  //    view saw (a fifth of the embedded OR's held-out view): nothing can reconstruct them, and
  //    the mean colour is the estimate of their colour with the least expected squared error,
  //    where black is about the worst (docs: bench/splat_recon/README.md).
  Background background = Background::Black;
  // Loss weights; 0 switches a term off (ablation). Anchors: DN-Splatter depth 0.2, normal 0.1;
  // [decision] defaults measured in bench/splat_recon.
  double depth_weight = 0.2;   // depth log-L1 against the depth prior, valid pixels only
  double normal_weight = 0.1;  // 1 - cos(rendered normal, normal from the depth prior)
  double scale_weight = 0.01;  // flatness: mean smallest scale (metres)
  // Extent along the training rays of Gaussians on the near side of a depth-prior discontinuity
  // (depth_edge_extent.hpp), in metres per Gaussian; 0 = off.
  double edge_extent_weight = 0;
  // Line-of-sight loss (line_of_sight_loss.hpp): the opacity each training pixel accumulates more
  // than floaters.tolerance in front of its depth prior, averaged over the pixels with a prior,
  // on the step's own view from the first line_of_sight_start fraction of the steps on. 0 = off.
  double line_of_sight_weight = 0;
  double line_of_sight_start = 0;
  // Coarse-to-fine: the first coarse_fraction of the steps render and compare at half resolution
  // (a quarter of the pixels), the rest at full resolution. 0 = off. [decision] 0.4: on the
  // embedded OR (footprint 12) 86 -> 78 s CPU for 500 steps and train PSNR 29.49 -> 29.99 dB
  // (bench/results/splat_recon_sweep.json).
  double coarse_fraction = 0.4;
  bool densify = true;
  DensityControlOptions density;
  // Gaussians pruned for sitting in the free space that the training views' depth priors observe
  // (free_space.hpp), at each densification round and every density.interval steps after growth
  // stops; off by default.
  FreeSpacePruneOptions floaters;
  // The training views' poses optimised with the Gaussians, then each held-out view's against its
  // photo (pose_correction.hpp); off by default.
  PoseRefinementOptions poses;
  // Early stop when the mean loss of the last `plateau_window` steps improves on the previous
  // window by less than plateau_tolerance (relative). 0 = off.
  int plateau_window = 0;
  double plateau_tolerance = 1e-3;
  LearningRates rates;
  AdamSettings adam;
  InitialiseOptions init;
  uint64_t seed = 0;  // view order and split sampling; not a param: the node's seed
};

// The params of splat.reconstruct: the fields above that a graph may set, the budget of
// `density` and the initialisation's source, footprint_factor and normal_thickness among them.
// The few a user sets first come first; the rest are marked advanced (`gslift nodes` lists them
// under the others). reconstruct() validates its options against it.
const ParamTable<ReconstructOptions>& reconstruct_param_table();
// The fields no graph sets, for benchmarks' sweeps (bench/splat_recon --set): learning rates,
// the density schedule and thresholds, the initialisation's stride and scale.
const ParamTable<ReconstructOptions>& reconstruct_tuning_table();

// Named settings of splat.reconstruct (its `recipe` param), each a group of params set at once.
//  none: the params' own defaults.
//  depth_prior: what met the held-out geometry targets on the embedded OR with a depth prior
//    (bench/splat_recon/README.md, "Where it stands"): the mean-colour background, the
//    line-of-sight prior as a loss from half of the steps and as pruning in two rounds running,
//    pruning of what lies behind or is hidden behind the prior, the edge-extent term, and every
//    test at the depth along each pixel's ray with a 2.5% margin.
enum class Recipe { None, DepthPrior };
const EnumNames<Recipe>& recipe_names();  // none, depth_prior
// The params a recipe sets (names of reconstruct_param_table) and their values.
const std::vector<std::pair<std::string, ParamValue>>& recipe_params(Recipe recipe);
// Sets the recipe's params in `o` (a C++ caller's `recipe:`).
void apply_recipe(ReconstructOptions& o, Recipe recipe);
// The recipes as a mode param's presets (ParamTable::presets): each recipe but none, with the
// names of the params it sets prefixed by `prefix` (a node that exposes them as recon_<name>).
std::map<std::string, ParamPreset> recipe_presets(const std::string& prefix = {});
// The names of the params some recipe sets, in recipe order.
std::vector<std::string> recipe_param_names();

// Mean of each loss term over the last 10% of the steps (at least one step).
struct LossSummary {
  double total = 0;
  // PSNR (dB) of the step's render against its target view (the photometric L2 of the render
  // the step made anyway): what the progress line shows as train PSNR. Read only, never a loss.
  double render_psnr = std::numeric_limits<double>::quiet_NaN();
  double features = 0;  // the FeatureObjective's loss (unweighted); 0 without one
  // Each term the run trained with (loss_terms.hpp), unweighted, by name, in the terms' order.
  std::vector<std::pair<std::string, double>> terms;
  // The named term's value; 0 for a term the run did not train with.
  double term(const std::string& name) const;
};

// Wall seconds spent in each phase of the optimisation loop, summed over the steps (profiling;
// bench/splat_recon reports them).
struct PhaseSeconds {
  double prepare = 0;   // initialisation and decoding the training targets
  double render = 0;    // rasterizer forward
  double losses = 0;    // loss values and their image gradients (SSIM, depth, normal, flatness)
  double backward = 0;  // rasterizer backward
  double adam = 0;      // parameter updates
  double density = 0;   // density statistics and densify/prune rounds
  double held_out_poses = 0;  // registering the held-out views' poses after training
  // Each loss term's share of `losses` (its evaluate(), gradient included; a ray term's own pass
  // over the tile lists too), by name in the terms' order: which term a step's time goes to.
  std::vector<std::pair<std::string, double>> terms;
};

struct ReconstructResult {
  GaussianModel model;
  size_t initial_gaussians = 0;
  size_t free_space_pruned = 0;  // Gaussians the free-space rules pruned, over all rounds
  int iterations_run = 0;
  bool stopped_early = false;
  size_t growth_refused = 0;  // densification candidates the Gaussian budget left out, all rounds
  // Training views with a depth prior. Without any, the depth-prior levers (line of sight, edge
  // extent, free-space pruning) do nothing, and reconstruct() warns when one is set.
  size_t depth_prior_views = 0;
  double seconds = 0;  // wall time of initialisation and optimisation
  PhaseSeconds phases;
  // The extent position rates and density thresholds were scaled by (reconstruction_extent).
  double scene_extent = 0;
  // The pruning round that removed the last Gaussians, when one did: its step and the reasons
  // (DensityChange's counts), so that an empty model says what emptied it.
  struct Emptied {
    int step = 0;
    size_t opacity = 0, scale = 0, free_space = 0;
  };
  std::optional<Emptied> emptied;
  LossSummary final_loss;
  std::vector<double> loss_history;  // total loss per step
  // Per view of the capture, its pose after refinement (the written pose where none ran).
  std::vector<Pose> poses;
  // Mean PSNR (dB) of the final model over the training / held-out views; NaN without such views.
  double train_psnr = 0, test_psnr = 0;
  // Held-out geometry against ground-truth depth (mean over the held-out views), when every view
  // has ground-truth depth (synthetic captures).
  std::optional<ViewGeometry> test_geometry;
  // With test_geometry: per held-out view (capture.test_views() order) the render with its
  // floaters, holes and uncovered surfaces painted (view_geometry).
  std::vector<cv::Mat3b> test_pictures;
};

// Why the model ended at its size (issue 15: "no more model than a scene needs"): "budget" when
// max_gaussians cut densification short, else "plateau" when the loss stopped falling and the run
// ended early, else "iterations" (the schedule ran out with the budget never reached).
const char* model_size_reason(const ReconstructResult& result);

// Called after every step with the step (steps done, total, its loss and render PSNR) and the
// Gaussian count. It may throw (e.g. gslift::Cancelled) to abort the reconstruction.
using ReconstructCallback = std::function<void(const TrainingStep& step, size_t gaussians)>;

// PSNR (dB) of a rendered RGB image (CV_32FC3, clamped to [0,1] here) against an 8-bit target,
// over the pixels of `mask` when one is given (NaN when it is empty of pixels).
double psnr(const cv::Mat& rendered, const cv::Mat& target_rgb8, const cv::Mat1b& mask = {});

// Mean PSNR of the model rendered at the given views against their RGB images (NaN when empty).
double mean_psnr(const GaussianModel& model, const Capture& capture, const std::vector<int>& views,
                 const Eigen::Vector3f& background = Eigen::Vector3f::Zero());

// Runs the reconstruction on the capture's training views. Deterministic for a fixed seed at any
// thread count. The targets of the training views (float RGB, depth, normals) are decoded once
// and kept for the run. With an `objective` its features train jointly with the geometry (the
// total loss adds objective->weight x L_feat) and come back in the model's feature channels.
// Throws std::invalid_argument naming the param when an option breaks its range
// (reconstruct_param_table), InputError when the capture has no training view or an image does
// not match its camera.
ReconstructResult reconstruct(const Capture& capture, const ReconstructOptions& options,
                              const ReconstructCallback& callback = {},
                              const FeatureObjective* objective = nullptr);

}  // namespace gslift
