// LangOR §1.3 instance lifting, the algorithm part of the lifting.cvp and lifting.mask_level
// nodes (their adapters need the render cache): from per-view rendered instance features and the
// 2D masks of the training views to 3D instances, each summarised by a prototype feature.
//
// CVP lifting: every mask's pixels get the Eq. 4 weights (cvp_weights.hpp); pixels of all masks
// of all views are drawn jointly with the alias method, HDBSCAN clusters the drawn pixels'
// features, noise is dropped, and each instance's prototype is the mean feature of its pixels
// (Eq. 5). Mask-level lifting (the paper's "w/o CVP-L" ablation, LaGa-style): one prototype per
// mask (masked mean feature), HDBSCAN over the mask prototypes of all views.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "nodes/lifting/hdbscan.hpp"
#include "nodes/scene/feature_map.hpp"
#include "nodes/scene/lifted_instances.hpp"
#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

// HDBSCAN settings for instance features [decisions]: cosine, since the contrastive loss (Eq. 3)
// shapes features by cosine; min_cluster_size 10 (LaGa/SAGA use 5..10); epsilon 0; min_samples 3
// [measured, docs/langor.md]. With min_samples = min_cluster_size = 10 the core distances (10th
// neighbour) bridge two objects that stand close and look alike (assistant surgeon and
// circulating nurse in the same gowns, the C-arm over the monitor): their features were
// separable (>= 98.8% of pixels nearest their own object's centroid) yet HDBSCAN kept them as
// one cluster, and one of the two classes lost its instance. The 3rd neighbour keeps the gap:
// embedded OR mIoU over seeds 0-4 60.7 -> 64.0 (seeds 2 and 3 +7 and +9, the others within 0.2).
HdbscanParams default_lifting_hdbscan();

// Masks of one view that overlap with IoU below `max_iou` show different objects (a view's SAM box
// masks are one per detected object; two boxes on one object give near-identical masks). Returns
// the cannot-link pairs between such masks, groups numbered by (view, mask) in MaskSet order
// (mask_group_ids); max_iou <= 0 gives none. A gslift addition to LangOR's lifting: HDBSCAN's
// excess of mass may otherwise keep two look-alike neighbours (the C-arm over the monitor) as one
// cluster although every view shows them as two masks. Measured on the embedded OR, seeds 0-4:
// mIoU 56.1 -> 59.4; seeds 2 and 3 got the C-arm back (IoU 0 -> 55 and 65), the others moved by
// at most 0.3 (docs/langor.md).
std::vector<std::pair<int, int>> same_view_cannot_links(const MaskSet& masks, double max_iou);
// Group id of masks.views[v].masks[m]: its position in (view, mask) order.
std::vector<std::vector<int>> mask_group_ids(const MaskSet& masks);

struct CvpLiftingParams {
  // Eq. 4 width in units of each mask's RMS radius; 0.5 in the paper, 0.7 in its ablation.
  double sigma = 0.5;
  // Sample budget [decision]: this many draws per mask, capped at max_samples in total (HDBSCAN
  // is O(n^2)). Draws are with replacement and then deduplicated, so a mask may get fewer.
  int samples_per_mask = 100;
  int max_samples = 20000;
  HdbscanParams hdbscan = default_lifting_hdbscan();
  // same_view_cannot_links; 0 = off (the paper's plain HDBSCAN).
  double cannot_link_iou = 0.5;
  uint64_t seed = 0;  // not a param: the node's seed
};

// Mask-level HDBSCAN settings [decision]: an instance is a handful of masks (one per training view
// that sees it, 4 in LangOR's split), not hundreds of pixels, so CVP's min_cluster_size 10 would
// leave everything noise. 2 masks make an instance; min_samples 1 makes the core distance the
// nearest other mask's. The rest as default_lifting_hdbscan().
HdbscanParams mask_level_hdbscan();

struct MaskLevelLiftingParams {
  HdbscanParams hdbscan = mask_level_hdbscan();
  double cannot_link_iou = 0.5;  // as CvpLiftingParams
};

// The params of lifting.cvp and lifting.mask_level: one entry per field above (the HDBSCAN
// fields they expose and cannot_link_iou are shared).
const ParamTable<CvpLiftingParams>& cvp_lifting_param_table();
const ParamTable<MaskLevelLiftingParams>& mask_level_lifting_param_table();

// views[i] goes with masks.views[i]. Throws std::invalid_argument when the counts differ, a mask
// does not match its feature map's size, or there are no mask pixels at all.
LiftedInstances cvp_lifting(const std::vector<FeatureMap>& views, const MaskSet& masks,
                            const CvpLiftingParams& params);

// Masks without pixels are skipped (no entry).
LiftedInstances mask_level_lifting(const std::vector<FeatureMap>& views, const MaskSet& masks,
                                   const MaskLevelLiftingParams& params);

}  // namespace gslift
