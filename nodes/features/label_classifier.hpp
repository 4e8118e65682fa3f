// Gaga's lift (lift.py, method-anchors §1.1 step 4): the consistent label maps of the memory bank
// lifted to the Gaussians with the geometry frozen. D features per Gaussian (zero-initialised, as
// Gaga when it loads a vanilla 3DGS model) and a 1x1 linear classifier over the rendered features,
// logits W F + b over the labels 0..L, trained together with the cross-entropy divided by ln(L+1)
// at sampled pixels (train_pixel_features), optionally with Gaga's 3D KL neighbour regulariser on
// the Gaussians' own class distributions. Gaga renders whole images for 10k steps; we sample.
// Proto-SaGa's "Cls" inference baseline (Table 4) trains the same classifier.
#pragma once

#include <cstdint>
#include <functional>

#include "base/training_step.hpp"
#include "nodes/features/neighbour_kl.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/label_maps.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct LabelClassifierOptions {
  int iterations = 1000;        // Gaga: 10k full-image steps; measured in docs/protosaga.md
  int dim = 16;                 // Gaga num_objects = 16
  double lr = 2.5e-3;           // Gaga feature_lr
  double classifier_lr = 5e-4;  // Gaga
  int pixels_per_view = 2048;   // sampled pixels per view and step [decision]
  double min_weight = 1e-2;     // blend weights dropped from the stored rows
  NeighbourKlOptions kl;        // Gaga's optional 3D neighbour regulariser (neighbour_kl.hpp)
  uint64_t seed = 0;            // not a param: the node's seed
};

const ParamTable<LabelClassifierOptions>& label_classifier_param_table();

struct LabelClassifierResult {
  GaussianModel model;  // the input geometry with dim trained features
  LabelClassifier classifier;
  double loss_start = 0, loss_end = 0;
  double seconds = 0;
};

// `labels`: consistent label maps (association.memory_bank), ids 0..labels.labels; maps of
// held-out views are ignored. Throws InputError like train_view_classifiers.
LabelClassifierResult train_label_classifier(const GaussianModel& model, const Capture& capture,
                                             const LabelMapSet& labels,
                                             const LabelClassifierOptions& options,
                                             const TrainingProgress& progress = {});

}  // namespace gslift
