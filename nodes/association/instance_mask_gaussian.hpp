// LangOR §1.3 "Matching" and "Instance semantics": ties the lifted 3D instances (prototypes f_S,
// Eq. 5) back to the 2D masks and forward to the Gaussians.
//   1. every pixel of every training mask gets an instance: a pixel that CVP lifting sampled keeps
//      its HDBSCAN cluster (a sampled noise pixel does not vote), every other ("unsampled") pixel
//      takes the prototype with maximal cos(F(p), f_S);
//   2. each mask takes the most frequent instance among its pixels (ties: the lower instance id);
//   3. each Gaussian takes the prototype with maximal cos(f_g, f_S), see AssociationParams for the
//      Gaussians left unassigned;
//   4. each instance's semantics come from the labels of its masks (instance_semantics.hpp).
// An instance that no mask chose gets the label "" and a zero embedding: it keeps its Gaussians
// (they are still one object) but text queries must skip it, since nothing says what it is.
// Parallel (TBB) over masks and over Gaussians, each writing only its own result, so the output
// does not depend on the thread count.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "nodes/scene/feature_map.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/instances.hpp"
#include "nodes/scene/lifted_instances.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/scene/text_encoder.hpp"
#include "nodes/splat/training_feature_maps.hpp"
#include "param/param_table.hpp"

namespace gslift {

enum class MaskVote { Count, Iou };
const EnumNames<MaskVote>& mask_vote_names();  // count, iou

struct AssociationParams {
  // [decision] A Gaussian whose blend weights summed over all training pixels stay below this
  // (in pixels) is left -1: its feature received (almost) no gradient in feature training, so its
  // most similar prototype is chance. 0.01 = a hundredth of a pixel over all training views.
  double min_contribution = 0.01;
  // [decision] A Gaussian joins its most similar instance only when cos(f_g, f_S) reaches this;
  // otherwise it stays -1 (background: walls, floor, anything no mask covered). Eq. 3 pulls
  // in-mask features to cos 1 with their mask's centroid and pushes the rest to cos <= 0, so 0.5
  // is the midpoint between the two hinge targets. -1 assigns every Gaussian with a feature.
  float min_similarity = 0.5f;
  // How a mask picks its instance (step 2).
  //  count: the paper's most frequent instance among its pixels.
  //  iou [decision, issue 11]: the instance whose region in the view fits the mask best, by IoU;
  //    the region of instance k is every pixel of the view whose instance (step 1's rule, with
  //    the unsampled pixels below min_similarity to every prototype left out) is k. A box mask
  //    that swallows a person standing at a table holds more person pixels than table pixels
  //    when the person is larger in the view, but covers the table's region better than the
  //    person's, whose pixels are mostly outside it.
  MaskVote mask_vote = MaskVote::Count;
};

// The params of association.instance_mask_gaussian: one entry per field above.
const ParamTable<AssociationParams>& association_param_table();

// For each view of `masks`, for each of its masks: the instance it matches (steps 1-2), -1 when
// none of its pixels votes. maps[i] goes with masks.views[i]; `lifted` must come from these maps
// and masks (its samples index them). Throws InputError when sizes or indices disagree.
// With MaskVote::Iou, steps 1-2 by the IoU rule of AssociationParams::mask_vote (min_similarity
// leaves unsampled pixels out of every region).
std::vector<std::vector<int>> match_masks(const std::vector<FeatureMap>& maps, const MaskSet& masks,
                                          const LiftedInstances& lifted,
                                          MaskVote vote = MaskVote::Count,
                                          float min_similarity = -1.f);

// Step 3. contribution: per Gaussian summed blend weight over the training views (empty = every
// Gaussian counts as seen). Gaussians with a zero feature stay -1 (cosine undefined). Throws
// InputError when the prototypes' width differs from the model's feature_dim.
std::vector<int32_t> match_gaussians(const GaussianModel& model,
                                     const std::vector<float>& contribution,
                                     const Eigen::MatrixXf& prototypes,
                                     const AssociationParams& params);

struct InstanceAssociation {
  InstanceSet instances;                   // mask_instance indexed like the `masks` given
  std::vector<int32_t> gaussian_instance;  // per Gaussian, -1 unassigned
  int training_masks = 0;                  // masks of the training views, each matched or not
  int matched_masks = 0;                   // those that matched an instance
};

// Steps 1-4 together on the training views of `masks` (render_training_feature_maps of these
// masks; `lifted` comes from them, and their contribution, if any, is step 3's). mask_instance
// is indexed like `masks`: the masks of held-out views are not matched (-1). Throws InputError
// when `views` does not come from `masks`.
InstanceAssociation associate_instances(const TrainingFeatureMaps& views, const MaskSet& masks,
                                        const LiftedInstances& lifted, const GaussianModel& model,
                                        const TextEncoder& encoder,
                                        const AssociationParams& params);

}  // namespace gslift
