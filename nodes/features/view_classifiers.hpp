// Proto-SaGa §3.1 (Eq. 5-8): D features per Gaussian and one cosine classifier per training view
// over that view's inconsistent SAM ids, sigma_k(p) = softmax(tau cos(w_k, F_k(p))) (Eq. 6),
// trained with the cross-entropy against the view's SAM partition (Eq. 7) at sampled pixels.
// Class 0 of a view is the pixels no SAM mask covers, classes 1..L_k its masks (Gaga's raw maps
// keep 0 as a class too). Two modes:
//  - frozen (the appendix variant): on a given reconstruction's geometry, every view every
//    iteration (train_pixel_features). L_CE is the only loss and Adam is invariant to its scale,
//    so lambda_CE plays no part.
//  - joint (the paper's main variant, Eq. 8): the capture is reconstructed with
//    L = L_rec + lambda_CE L_CE, the features rendered with the colour pass and L_CE's gradient
//    reaching the geometry too (reconstruct()'s FeatureObjective); one view per step, as the
//    reconstruction visits them.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "base/training_step.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/label_maps.hpp"
#include "nodes/splat/reconstruct.hpp"
#include "param/param_table.hpp"

namespace gslift {

enum class FeatureTraining { Frozen, Joint };
const EnumNames<FeatureTraining>& feature_training_names();  // frozen, joint

struct ViewClassifierOptions {
  FeatureTraining training = FeatureTraining::Frozen;
  // The paper trains 30k joint steps; on frozen geometry 300 steps give the held-out mIoU of 1000
  // (embedded OR seed 0: 51.9 / 51.6, docs/protosaga.md) in a third of the time.
  int iterations = 300;
  int dim = 16;                 // D (Proto-SaGa, Gaga: 16)
  double tau = 10;              // temperature of Eq. 6
  double lr = 2.5e-3;           // features (paper)
  double classifier_lr = 5e-4;  // classifiers (paper)
  int pixels_per_view = 2048;   // sampled pixels per view and step [decision]
  // Features and classifier rows start as N(0, init_std^2) draws. Small: a Gaussian that no
  // training pixel reaches keeps its random direction and shows as a speckle of a random label in
  // a novel view (embedded OR seed 0: held-out mIoU 45 at 0.1, 54-56 at 0.01).
  double init_std = 0.01;
  double min_weight = 1e-2;  // blend weights dropped from the stored rows (features.contrastive)
  // Class 0 (pixels no SAM mask covers) means the same in every view, unlike mask ids: one row
  // shared by all classifiers pulls the uncovered surfaces (walls, floor) to one direction, so
  // that they get a prototype of their own at inference [decision, measured in
  // docs/protosaga.md]; false gives every view its own class-0 row.
  bool shared_background = true;
  // Joint training only: the weight of L_CE in Eq. 8 (paper 0.05) and the reconstruction it runs
  // inside (params recon_<name> for the main ones of splat.reconstruct, its defaults otherwise);
  // `iterations` is unused there (the reconstruction's steps are the training steps).
  double lambda_ce = 0.05;
  Recipe recon_recipe = Recipe::None;  // resolved by the graph (ParamSpec::presets), not read here
  ReconstructOptions recon;
  uint64_t seed = 0;  // not a param: the node's seed
};

const ParamTable<ViewClassifierOptions>& view_classifier_param_table();

struct ViewClassifierResult {
  GaussianModel model;  // frozen: the input geometry with dim trained features; joint: the model
  ViewClassifiers classifiers;
  // Mean cross-entropy over the views (frozen); joint: of the first step's view, and the mean
  // over the last 10% of the steps.
  double loss_start = 0, loss_end = 0;
  size_t cache_bytes = 0;
  double seconds = 0;
  // Joint: the reconstruction's own records (model, PSNR, losses; its model moved to `model`).
  std::optional<ReconstructResult> recon;
};

// Frozen training on `model`'s geometry. `partitions`: the raw SAM partitions
// (association.sam_partition), one per view; maps of held-out views are ignored. Throws InputError
// for an empty model, bad options, a map that does not fit its view, or no training view.
ViewClassifierResult train_view_classifiers(const GaussianModel& model, const Capture& capture,
                                            const LabelMapSet& partitions,
                                            const ViewClassifierOptions& options,
                                            const TrainingProgress& progress = {});

// Joint training: reconstructs `capture` with options.recon and the view classifiers' L_CE
// (weight options.lambda_ce) trained together; the seed of the reconstruction is options.seed.
// Throws like train_view_classifiers and reconstruct().
ViewClassifierResult train_view_classifiers_jointly(const Capture& capture,
                                                    const LabelMapSet& partitions,
                                                    const ViewClassifierOptions& options,
                                                    const TrainingProgress& progress = {});

}  // namespace gslift
